#!/usr/bin/env python3
"""store_probability study on matrix cells (ids as in OUT/scenes/): map size, phase seconds, error, C = err^2 x (trace+build+render); seeds interleaved."""
import json, subprocess, sys, os, math, argparse, statistics
ap = argparse.ArgumentParser()
ap.add_argument('cells', nargs='+')
ap.add_argument('--seeds', type=int, default=2)
ap.add_argument('--q', default='1,0.25,0.0625')
ap.add_argument('--set', action='append', default=[])
ap.add_argument('--threads', type=int, default=1)
ap.add_argument('--matrix', default='out/matrix', help='a vpm bench matrix --out folder: its scenes/ and cached references/')
ap.add_argument('--media', default='media', help='folder with blob.vdb and plume.vdb')
ap.add_argument('--vpm', default='build/vpm')
ap.add_argument('--old-vpm', default='build/vpm', help='the binary of methods named old=old:GATHER')
ap.add_argument('--tmp', default='out/cells', help='scratch folder for the renders')
a = ap.parse_args()
os.makedirs(a.tmp, exist_ok=True)
M = a.matrix
MEDIA = os.path.abspath(a.media)
vpm = a.vpm
refs = {}
for f in os.listdir(M + '/references'):
    if f.endswith('.json'):
        d = json.load(open(M + '/references/' + f)); refs[d['scene']] = (f[:-5], d['noise_rel_variance'])
for cell in a.cells:
    scene = f'{M}/scenes/{cell}.toml'
    ref, noise = refs[cell]
    qs = a.q.split(',')
    res = {q: [] for q in qs}
    for seed in range(1, a.seeds + 1):
        for q in qs:
            out = a.tmp + '/store.exr'
            cmd = [vpm, 'render', scene, '--set', 'render.integrator="photon_map"', '--set', f'photons.store_probability={q}',
                   '--set', f'render.seed={seed}', '--threads', str(a.threads), '-o', out, '-q']
            if 'blob' in cell or 'plume' in cell:
                cmd += ['--set', 'media.0.file="' + MEDIA + '/' + ('blob' if 'blob' in cell else 'plume') + '.vdb"']
            for s in a.set: cmd += ['--set', s]
            subprocess.run(cmd, check=True)
            d = json.load(open(a.tmp + '/store.json'))
            c = json.loads(subprocess.run([vpm, 'compare', '--json', out, f'{M}/references/{ref}.exr'],
                                          capture_output=True, text=True, check=True).stdout)
            ph = d['phases']
            res[q].append((c['luminance_rel_rmse'] ** 2 - noise, c['luminance_rel_bias'], ph['trace']['seconds'], ph['build']['seconds'],
                           ph['render']['seconds'], d['photons']['stored'], d['photons']['collisions'], d['photons']['emitted']))
    print(cell, flush=True)
    for q in qs:
        r = res[q]
        m = lambda i: statistics.mean(x[i] for x in r)
        tot = m(2) + m(3) + m(4)
        print(f'  q={q}: stored {m(5):.0f} ({m(5)/m(7):.3f}/emitted, collisions/emitted {m(6)/m(7):.2f}) trace {m(2):.2f} build {m(3):.3f} render {m(4):.2f} s '
              f'rmse {math.sqrt(max(m(0),0)):.3f} bias {m(1):+.3f} C {m(0)*tot:.3g}', flush=True)
