#!/usr/bin/env python3
"""The auto plan's cost model against the clock (lib/render/plan/work_units.cpp, docs/studies/auto_plan.md section 19): per
matrix cell, the pilot's counted work units per camera sample of each candidate (collision, march,
continue; read from the run's sidecar, so the binary's own weights) over the user CPU nanoseconds per
sample of that candidate forced. CPU per sample is the difference of two fixed-work runs (288 and 32
samples per pixel, one thread, getrusage of the child), so the photon pass and start-up cancel and
the machine's load mostly does not enter. "continue" is timed as the collision gather over a
one-photon map (every estimate then continues the path: the same estimator).

  scripts/work_units_check.py --matrix OUT [--cells CELL,CELL] [--vpm build/vpm] [--jsonl FILE]

A ratio near 1 for every candidate of a cell is what the plan needs: its choice compares them.
With --photon-pass the photon pass is checked instead: counted work units per emitted photon (the
plan's photon_cost) over user CPU ns per emitted photon, from the difference of two one-sample runs
with 4e5 and 1e5 photons (the collision gather forced, so no pilot)."""
import argparse, json, os, statistics, sys, tempfile

from timed_render import timed_render

ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
ap.add_argument('--matrix', required=True, help='a vpm bench matrix --out folder (its scenes/)')
ap.add_argument('--cells', default='', help='comma-separated cell ids (default: every scene in OUT/scenes)')
ap.add_argument('--vpm', default='build/vpm')
ap.add_argument('--jsonl', default='', help='append one JSON line per cell (counts and times) here')
ap.add_argument('--photon-pass', action='store_true', help='check the photon pass per emitted photon instead of the camera samples')
args = ap.parse_args()

scenes = os.path.join(args.matrix, 'scenes')
if not os.path.isdir(scenes):
    sys.exit(f'work_units_check: {scenes} does not exist (run vpm bench matrix --out {args.matrix} first)')
cells = args.cells.split(',') if args.cells else sorted(f[:-5] for f in os.listdir(scenes) if f.endswith('.toml'))
tmp = tempfile.mkdtemp(prefix='vpm-work-units-')
CANDIDATES = [('collision', ['photons.gather="collision"']), ('march', ['photons.gather="march"']),
              ('continue', ['photons.gather="collision"', 'photons.count=1'])]


def run(cell, sets):
    """User CPU seconds of one render of the cell, and its sidecar."""
    return timed_render(args.vpm, os.path.join(scenes, cell + '.toml'), sets, tmp, 'work_units_check')


if args.photon_pass:
    ratios = []
    print(f'{"cell":44s}{"photon pass":>24s}   (counted / real ns per emitted photon)')
    for cell in cells:
        _, side = run(cell, ['render.spp=32', 'render.time_limit=1'])   # the plan's photon_cost (a short budget: the pilot alone matters)
        counted = side['photons']['auto_gather']['photon_cost']
        sets = ['photons.gather="collision"', 'render.spp=1']
        lo, a = run(cell, sets + ['photons.count=100000'])
        hi, b = run(cell, sets + ['photons.count=400000'])
        real = (hi - lo) / (b['photons']['emitted'] - a['photons']['emitted']) * 1e9
        ratios.append(counted / real)
        print(f'{cell:44s}{counted:9.0f} / {real:6.0f} = {counted / real:4.2f}', flush=True)
        if args.jsonl:
            with open(args.jsonl, 'a') as f:
                f.write(json.dumps({'cell': cell, 'photon_cost': counted, 'ns_per_photon': real, 'photons': b['photons']}) + '\n')
    print(f'photon pass: counted / real over {len(ratios)} cells: min {min(ratios):.2f}, median {statistics.median(ratios):.2f}, max {max(ratios):.2f}')
    sys.exit(0)

ratios = {name: [] for name, _ in CANDIDATES}
print(f'{"cell":44s}' + ''.join(f'{name:>24s}' for name, _ in CANDIDATES) + '   (counted / real ns per sample)')
for cell in cells:
    _, side = run(cell, ['render.spp=32'])
    auto = side['photons']['auto_gather']
    real = {}
    for name, sets in CANDIDATES:
        lo, _ = run(cell, sets + ['render.spp=32'])
        hi, _ = run(cell, sets + ['render.spp=288'])
        pixels = side['config']['render']['width'] * side['config']['render']['height']
        real[name] = (hi - lo) / (256 * pixels) * 1e9
    line = f'{cell:44s}'
    for c, (name, _) in enumerate(CANDIDATES):
        counted = auto['sample_cost'][auto['candidates'].index(name)]
        ratio = counted / real[name] if real[name] > 0 else float('nan')
        if real[name] >= 150:   # below it the 10 ms rusage resolution is 25% of the difference
            ratios[name].append(ratio)
        line += f'{counted:9.0f} / {real[name]:6.0f} = {ratio:4.2f}'
    print(line, flush=True)
    if args.jsonl:
        with open(args.jsonl, 'a') as f:
            f.write(json.dumps({'cell': cell, 'auto': auto, 'ns': real}) + '\n')
for name, v in ratios.items():
    if v:
        print(f'{name}: counted / real over {len(v)} cells: min {min(v):.2f}, median {statistics.median(v):.2f}, max {max(v):.2f}')
