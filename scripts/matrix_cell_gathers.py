#!/usr/bin/env python3
"""Interleaved gather comparison on matrix cells: error per sample and render seconds per sample.
usage: scripts/matrix_cell_gathers.py CELL... --matrix OUT [--seeds N] [--spp S] [--methods name=old|new:GATHER,...] [--set k=v ...]"""
import json, subprocess, sys, os, math, argparse, statistics
ap = argparse.ArgumentParser()
ap.add_argument('cells', nargs='+')
ap.add_argument('--seeds', type=int, default=3)
ap.add_argument('--spp', type=int, default=16)
ap.add_argument('--methods', default='coll=new:collision,old=old:march,new=new:march')
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
bins = {'old': a.old_vpm, 'new': a.vpm}
refs = {}
for f in os.listdir(M + '/references'):
    if f.endswith('.json'):
        d = json.load(open(M + '/references/' + f)); refs[d['scene']] = (f[:-5], d['noise_rel_variance'])
methods = [m.split('=') for m in a.methods.split(',')]
for cell in a.cells:
    scene = f'{M}/scenes/{cell}.toml'
    ref, noise = refs[cell]
    res = {name: [] for name, _ in methods}
    for seed in range(1, a.seeds + 1):
        for name, spec in methods:
            b, gather = spec.split(':')
            out = f'{a.tmp}/run_{name}.exr'
            cmd = [bins[b], 'render', scene, '--set', 'media.0.file="' + MEDIA + '/' + ('blob' if 'blob' in cell else 'plume') + '.vdb"',
                   '--set', 'render.integrator="photon_map"', '--set', f'photons.gather="{gather}"', '--set', f'render.seed={seed}',
                   '--set', f'render.spp={a.spp}', '--threads', str(a.threads), '-o', out, '-q']
            for s in a.set: cmd += ['--set', s]
            subprocess.run(cmd, check=True)
            d = json.load(open(out[:-4] + '.json'))
            c = json.loads(subprocess.run([bins['new'], 'compare', '--json', out, f'{M}/references/{ref}.exr'],
                                          capture_output=True, text=True, check=True).stdout)
            res[name].append((c['luminance_rel_rmse'] ** 2 - noise, c['luminance_rel_bias'], d['phases']['render']['seconds'],
                              d['phases']['trace']['seconds'], d['photons'].get('march_weight_max', float('nan')),
                              d['photons'].get('march_weight_mean', float('nan'))))
    W, H = 32, 32
    line = [cell]
    for name, _ in methods:
        r = res[name]
        e2 = statistics.mean(x[0] for x in r); bias = statistics.mean(x[1] for x in r)
        sec = statistics.mean(x[2] for x in r); us = sec / (W * H * a.spp) * 1e6
        wmax = max(x[4] for x in r); wmean = statistics.mean(x[5] for x in r)
        line.append(f'{name}: rmse {math.sqrt(max(e2,0)):.3f} bias {bias:+.3f} {us:.1f}us/spl C {e2*sec:.3g} w {wmax:.3g}/{wmean:.3g}')
    print(' | '.join(line), flush=True)
