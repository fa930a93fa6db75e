#!/usr/bin/env python3
"""store_probability 1 vs "auto" at equal time (render.time_limit) on matrix cells (ids as in OUT/scenes/), interleaved per seed."""
import json, subprocess, sys, os, math, argparse, statistics
ap = argparse.ArgumentParser()
ap.add_argument('cells', nargs='+')
ap.add_argument('--seeds', type=int, default=2)
ap.add_argument('--seconds', type=float, default=3)
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
    qs = ['1', '"auto"']
    res = {q: [] for q in qs}
    for seed in range(1, a.seeds + 1):
        for q in qs:
            out = a.tmp + '/auto.exr'
            cmd = [vpm, 'render', scene, '--set', 'render.integrator="photon_map"', '--set', f'photons.store_probability={q}',
                   '--set', f'render.seed={seed}', '--set', f'render.time_limit={a.seconds}', '--threads', str(a.threads), '-o', out, '-q']
            if 'blob' in cell or 'plume' in cell:
                cmd += ['--set', 'media.0.file="' + MEDIA + '/' + ('blob' if 'blob' in cell else 'plume') + '.vdb"']
            for s in a.set: cmd += ['--set', s]
            subprocess.run(cmd, check=True)
            d = json.load(open(a.tmp + '/auto.json'))
            c = json.loads(subprocess.run([vpm, 'compare', '--json', out, f'{M}/references/{ref}.exr'],
                                          capture_output=True, text=True, check=True).stdout)
            ph = d['phases']; p = d['photons']
            res[q].append((c['luminance_rel_rmse'] ** 2 - noise, ph['trace']['seconds'], ph['build']['seconds'], ph['render']['seconds'],
                           p['stored'] / d['passes']['count'], d['passes']['count'], p.get('store_probability_used', 1), p['stored'] / max(1, p.get('storing_walks', 1))))
    print(cell, flush=True)
    for q in qs:
        r = res[q]; m = lambda i: statistics.mean(x[i] for x in r)
        print(f'  q={q}: q_used {m(6):.3f} stored/pass {m(4):.0f} (per storing walk {m(7):.2f}) passes {m(5):.1f} trace {m(1):.2f} build {m(2):.2f} render {m(3):.2f} s rmse {math.sqrt(max(m(0),0)):.4f}', flush=True)
