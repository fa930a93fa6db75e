#!/usr/bin/env python3
"""Error and time of methods on single cells of a `vpm bench matrix --out OUT` folder, decomposed
(docs/studies/scene_matrix.md section 11.11): per cell and method, CPU seconds of the whole process (getrusage, so the
machine's load does not enter), samples per pixel, squared relative error against the cell's cached
reference minus the reference's own noise, the variance from the two seeds' difference, the rest
(bias^2 and the reference's error), C = error^2 x CPU and the per-sample variance (variance x spp).
Interleaved: per seed, per cell, every method.

  scripts/cell_decompose.py --matrix OUT --cells CELL,CELL \\
      --methods 'pt=render.spp=128|pm=render.integrator="photon_map";photons.gather="collision"' \\
      [--vpm build/vpm] [--seeds 1,2] [--threads 1]

A method's sets may start with @BINARY to run another vpm build (before / after comparisons)."""
import argparse, csv, json, os, resource, subprocess

ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
ap.add_argument('--matrix', required=True, help='a vpm bench matrix --out folder (scenes/, references/, matrix.csv)')
ap.add_argument('--cells', required=True, help='comma-separated cell ids')
ap.add_argument('--methods', required=True, help='NAME=set;set|NAME2=@BINARY;set...')
ap.add_argument('--seeds', default='1,2')
ap.add_argument('--vpm', default='build/vpm')
ap.add_argument('--threads', default='1')
ap.add_argument('--tmp', default='out/cells')
a = ap.parse_args()
os.makedirs(a.tmp, exist_ok=True)
refs = {r['cell']: (r['reference'], float(r['reference_noise'])) for r in csv.DictReader(open(a.matrix + '/matrix.csv'))}
methods = []
for m in a.methods.split('|'):
    name, sets = m.split('=', 1)
    sets = [s for s in sets.split(';') if s]
    binary = a.vpm
    if sets and sets[0].startswith('@'):
        binary, sets = sets[0][1:], sets[1:]
    methods.append((name, binary, sets))


def cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def compare(vpm, image, reference):
    out = subprocess.run([vpm, 'compare', '--json', image, reference], capture_output=True, text=True, check=True).stdout
    return json.loads(out)


res = {}
for seed in [int(s) for s in a.seeds.split(',')]:
    for cell in a.cells.split(','):
        for name, binary, sets in methods:
            out = f'{a.tmp}/{cell}-{name}-{seed}.exr'
            cmd = ['nice', binary, 'render', f'{a.matrix}/scenes/{cell}.toml', '-o', out, '--threads', a.threads, '-q',
                   '--set', f'render.seed={seed}']
            for s in sets:
                cmd += ['--set', s]
            c0 = cpu()
            subprocess.run(cmd, check=True)
            seconds = cpu() - c0
            j = json.load(open(out[:-4] + '.json'))
            ref, noise = refs[cell]
            e = compare(a.vpm, out, f'{a.matrix}/references/{ref}.exr')
            pixels = j['config']['render']['width'] * j['config']['render']['height']
            res.setdefault((cell, name), []).append(dict(cpu=seconds, phases={k: v['seconds'] for k, v in j['phases'].items()},
                                                         rmse=e['relative_rmse'], bias=e['relative_bias'], out=out, noise=noise,
                                                         spp=j['render']['samples'] / pixels))
print(f"{'cell':40s} {'method':10s} {'cpu s':>7s} {'spp':>6s} {'mse-noise':>10s} {'var(pair)':>10s} {'rest':>10s} "
      f"{'bias':>8s} {'C=mse*cpu':>10s} {'V/sample':>9s}  phases (wall s)")
for (cell, name), rs in res.items():
    n = len(rs)
    seconds = sum(r['cpu'] for r in rs) / n
    mse = sum(r['rmse'] ** 2 for r in rs) / n - rs[0]['noise']
    var = compare(a.vpm, rs[0]['out'], rs[1]['out'])['relative_rmse'] ** 2 / 2 if n >= 2 else float('nan')
    spp = sum(r['spp'] for r in rs) / n
    bias = sum(r['bias'] for r in rs) / n
    phases = ' '.join(f"{k}={sum(r['phases'].get(k, 0) for r in rs) / n:.3f}" for k in ['pilot', 'trace', 'build', 'render']
                      if k in rs[0]['phases'])
    print(f"{cell:40s} {name:10s} {seconds:7.3f} {spp:6.0f} {mse:10.3e} {var:10.3e} {mse - var:10.3e} {bias:+8.4f} "
          f"{mse * seconds:10.3e} {var * spp:9.3e}  {phases}")
