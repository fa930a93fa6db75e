#!/usr/bin/env python3
"""Interleaved comparisons on single cells of a `vpm bench matrix --out OUT` folder (its scenes/ and
cached references/), seeds interleaved, error against the cell's reference minus the reference's own
noise. Three studies (docs/studies/march.md section 11.5 and 11.6):

  gathers     error per sample and render time per sample of photon-map gathers, each method
              NAME=BIN:GATHER with BIN old (--old-vpm) or new (--vpm); GATHER "path" is the path
              tracer, GATHER+point the gather with photons.extinction = "point"
  store       fixed photons.store_probability values (--q): map size, phase times, C = err^2 x time
  store-auto  photons.store_probability 1 against "auto" at equal time (render.time_limit = --seconds)

usage: scripts/matrix_cells.py STUDY CELL... --matrix OUT [--seeds N] [--set key=value ...]"""
import argparse, json, math, os, statistics, subprocess

ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
ap.add_argument('study', choices=['gathers', 'store', 'store-auto'])
ap.add_argument('cells', nargs='+')
ap.add_argument('--seeds', type=int, default=None, help='seeds 1..N (default 3 for gathers, else 2)')
ap.add_argument('--spp', type=int, default=16, help='gathers: samples per pixel')
ap.add_argument('--methods', default='coll=new:collision,old=old:march,new=new:march', help='gathers: NAME=BIN:GATHER,...')
ap.add_argument('--q', default='1,0.25,0.0625', help='store: the store probabilities')
ap.add_argument('--seconds', type=float, default=3, help='store-auto: render.time_limit')
ap.add_argument('--set', action='append', default=[])
ap.add_argument('--threads', type=int, default=1)
ap.add_argument('--matrix', default='out/matrix', help='a vpm bench matrix --out folder')
ap.add_argument('--media', default='media', help='folder with blob.vdb and plume.vdb')
ap.add_argument('--vpm', default='build/vpm')
ap.add_argument('--old-vpm', default='build/vpm', help='gathers: the binary of methods NAME=old:GATHER')
ap.add_argument('--tmp', default='out/cells', help='scratch folder for the renders')
a = ap.parse_args()
seeds = a.seeds or (3 if a.study == 'gathers' else 2)
os.makedirs(a.tmp, exist_ok=True)
media = os.path.abspath(a.media)
bins = {'old': a.old_vpm, 'new': a.vpm}
refs = {}
for f in os.listdir(a.matrix + '/references'):
    if f.endswith('.json'):
        d = json.load(open(a.matrix + '/references/' + f))
        refs[d['scene']] = (f[:-5], d['noise_rel_variance'])


def render(cell, binary, sets, name):
    """Renders the cell with the photon map and `sets`; returns (sidecar, error^2 minus reference noise, bias)."""
    out = f'{a.tmp}/{name}.exr'
    cmd = [binary, 'render', f'{a.matrix}/scenes/{cell}.toml', '--set', 'render.integrator="photon_map"',
           '--threads', str(a.threads), '-o', out, '-q']
    if 'blob' in cell or 'plume' in cell:
        cmd += ['--set', 'media.0.file="' + media + '/' + ('blob' if 'blob' in cell else 'plume') + '.vdb"']
    for s in sets + a.set:
        cmd += ['--set', s]
    subprocess.run(cmd, check=True)
    ref, noise = refs[cell]
    c = json.loads(subprocess.run([a.vpm, 'compare', '--json', out, f'{a.matrix}/references/{ref}.exr'],
                                  capture_output=True, text=True, check=True).stdout)
    return json.load(open(out[:-4] + '.json')), c['luminance_rel_rmse'] ** 2 - noise, c['luminance_rel_bias']


def mean(rows, i):
    return statistics.mean(r[i] for r in rows)


for cell in a.cells:
    if a.study == 'gathers':
        methods = [m.split('=') for m in a.methods.split(',')]
        res = {name: [] for name, _ in methods}
        for seed in range(1, seeds + 1):
            for name, spec in methods:
                binary, gather = spec.split(':')
                sets = [f'render.seed={seed}', f'render.spp={a.spp}']
                # GATHER "path": the path tracer; GATHER+point: the gather with photons.extinction = "point"
                sets += ['render.integrator="path"'] if gather == 'path' else [f'photons.gather="{gather.split("+")[0]}"']
                if gather.endswith('+point'):
                    sets.append('photons.extinction="point"')
                d, e2, bias = render(cell, bins[binary], sets, 'run_' + name)
                p, ph = d.get('photons', {}), d['phases']
                res[name].append((e2, bias, ph['render']['seconds'], p.get('march_weight_max', float('nan')),
                                  p.get('march_weight_mean', float('nan')),
                                  sum(ph[k]['seconds'] for k in ('trace', 'build', 'render') if k in ph)))
        line = [cell]
        for name, _ in methods:
            r = res[name]
            e2, sec = mean(r, 0), mean(r, 2)
            us = sec / (32 * 32 * a.spp) * 1e6
            line.append(f'{name}: rmse {math.sqrt(max(e2, 0)):.3f} bias {mean(r, 1):+.3f} {us:.1f}us/spl C {e2 * sec:.3g} '
                        f'C_total {e2 * mean(r, 5):.3g} '
                        f'w {max(x[3] for x in r):.3g}/{mean(r, 4):.3g}')
        print(' | '.join(line), flush=True)
        continue
    qs = a.q.split(',') if a.study == 'store' else ['1', '"auto"']
    res = {q: [] for q in qs}
    for seed in range(1, seeds + 1):
        for q in qs:
            sets = [f'photons.store_probability={q}', f'render.seed={seed}']
            if a.study == 'store-auto':
                sets.append(f'render.time_limit={a.seconds}')
            d, e2, bias = render(cell, a.vpm, sets, 'store')
            ph, p, passes = d['phases'], d['photons'], d['passes']['count']
            res[q].append((e2, bias, ph['trace']['seconds'], ph['build']['seconds'], ph['render']['seconds'], p['stored'],
                           p['collisions'], p['emitted'], passes, p.get('store_probability_used', 1),
                           p['stored'] / max(1, p.get('storing_walks', 1))))
    print(cell, flush=True)
    for q in qs:
        r = res[q]
        m = lambda i: mean(r, i)
        rmse = math.sqrt(max(m(0), 0))
        if a.study == 'store':
            tot = m(2) + m(3) + m(4)
            print(f'  q={q}: stored {m(5):.0f} ({m(5) / m(7):.3f}/emitted, collisions/emitted {m(6) / m(7):.2f}) trace {m(2):.2f} '
                  f'build {m(3):.3f} render {m(4):.2f} s rmse {rmse:.3f} bias {m(1):+.3f} C {m(0) * tot:.3g}', flush=True)
        else:
            print(f'  q={q}: q_used {m(9):.3f} stored/pass {m(5) / m(8):.0f} (per storing walk {m(10):.2f}) passes {m(8):.1f} '
                  f'trace {m(2):.2f} build {m(3):.2f} render {m(4):.2f} s rmse {rmse:.4f}', flush=True)
