#!/usr/bin/env python3
"""The kNN query's price against the map's size (lib/render/plan/work_units.cpp, docs/studies/march.md section 25).

Per matrix cell and photons.count: user CPU per camera sample of the forced collision gather and
march (288 - 32 spp, one thread, getrusage of the child) and the auto pilot's counted operations per
sample at the same count; then the least-squares fit of log(counted / real) with a used query priced
knn x factor x (1 + s log2(stored / 16384)), knn = 700 + 280 k (k = 32), one factor for grids and one
for homogeneous media, the other terms at the binary's prices below (keep them in step with
work_units.cpp). Runs under 800 ns per sample (the rusage resolution) or with fewer than 1000
stored photons are left out of the fit.

  scripts/query_price_fit.py --matrix OUT [--vpm build/vpm] [--runs CELL=COUNT,COUNT ...] [--jsonl FILE]
"""
import argparse, json, math, os, sys, tempfile

from timed_render import timed_render

ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
ap.add_argument('--matrix', required=True, help='a vpm bench matrix --out folder (its scenes/)')
ap.add_argument('--vpm', default='build/vpm')
ap.add_argument('--runs', nargs='*', default=['blob-tau1-a0.9-g0-point-s1=1e5,1e6,4e6', 'blob-tau10-a0.9-g0-point-s1=1e4,1e5,1e6,4e6',
                                              'box-tau1-a0.9-g0-point-s1=1e4,1e5,1e6,6e6', 'plume-tau1-a0.9-g0-point-s1=1e5,1e6,8e6',
                                              'blob-tau3-a0.9-g0-point-s1=1e5,1e6,4e6', 'blob-tau1-a0.9-g0-spot-s1=1e5,1e6'])
ap.add_argument('--jsonl', default='', help='read the runs from this file if it exists, else write them there')
args = ap.parse_args()

OTHER = {'grid': dict(ray=300, lookup=40, step=10, wide=200), 'hom': dict(ray=120, lookup=5, step=0, wide=200)}
KNN = 700 + 280 * 32
tmp = tempfile.mkdtemp(prefix='vpm-query-price-')


def run(cell, sets):
    return timed_render(args.vpm, os.path.join(args.matrix, 'scenes', cell + '.toml'), sets, tmp, 'query_price_fit', quiet=True)


records = []
if args.jsonl and os.path.exists(args.jsonl):
    records = [json.loads(l) for l in open(args.jsonl)]
else:
    for spec in args.runs:
        cell, counts = spec.split('=')
        for n in (int(float(c)) for c in counts.split(',')):
            _, side = run(cell, [f'photons.count={n}', 'render.spp=32'])
            a = side['photons']['auto_gather']
            rec = {'cell': cell, 'count': n, 'stored': side['photons']['stored'],
                   'auto': {k: a[k] for k in ('candidates', 'queries_per_sample', 'map_used_per_sample', 'rays_per_sample',
                                              'lookups_per_sample', 'steps_per_sample')}}
            pixels = side['config']['render']['width'] * side['config']['render']['height']
            for g in ('collision', 'march'):
                lo, _ = run(cell, [f'photons.count={n}', f'photons.gather="{g}"', 'render.spp=32'])
                hi, _ = run(cell, [f'photons.count={n}', f'photons.gather="{g}"', 'render.spp=288'])
                rec[g + '_ns'] = (hi - lo) / (256 * pixels) * 1e9
            rec['load'] = open('/proc/loadavg').read().split()[:3]
            records.append(rec)
            print(cell, n, rec['stored'], round(rec['collision_ns']), round(rec['march_ns']), flush=True)
    if args.jsonl:
        with open(args.jsonl, 'w') as f:
            f.writelines(json.dumps(r) + '\n' for r in records)

rows = []   # (kind, stored, used queries, other units, real ns)
for r in records:
    kind = 'grid' if not r['cell'].startswith(('box', 'sphere')) else 'hom'
    w, a = OTHER[kind], r['auto']
    for g in ('collision', 'march'):
        i = a['candidates'].index(g)
        q = a['queries_per_sample'][i]
        used = min(q, a['map_used_per_sample'][i])
        other = (w['ray'] * a['rays_per_sample'][i] + w['lookup'] * a['lookups_per_sample'][i] +
                 w['step'] * a['steps_per_sample'][i] + w['wide'] * (q - used))
        if r[g + '_ns'] >= 800 and r['stored'] >= 1000:
            rows.append((kind, r['stored'], used, other, r[g + '_ns']))


def rms(fg, fh, s):
    e = [math.log((o + KNN * (fg if k == 'grid' else fh) * (1 + s * math.log2(n / 16384)) * u) / real) for k, n, u, o, real in rows]
    return math.sqrt(sum(x * x for x in e) / len(e))


print(f'{len(rows)} runs fitted; flat 0.75 / 0.5: rms log {rms(0.75, 0.5, 0.0):.3f}')
best = min((rms(fg / 200, fh / 200, s / 1000), fg / 200, fh / 200, s / 1000)
           for fg in range(40, 181) for fh in range(40, 181) for s in range(0, 101, 5))
print(f'fit: factor grids {best[1]:.3f}, homogeneous {best[2]:.3f}, growth per doubling {best[3]:.3f}: rms log {best[0]:.3f}')
