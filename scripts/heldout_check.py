#!/usr/bin/env python3
"""The photon map's defaults against the path tracer at equal time on any scene files (bench/heldout/):
unlike `vpm bench equal-time`, which renders fixed photon and sample counts, each run here sets only
render.integrator and render.time_limit, so the automatic plan is what is measured. Per scene and
seed, `vpm render SCENE --set render.time_limit=BUDGET` with the path tracer and with the photon map
and with each of --integrators (photon_map and auto; each binary of --vpm, interleaved), error against a long path-traced reference (rendered once with
--reference-seconds on seed 99 and cached beside the outputs by scene file name), and the photon map's
time to equal error over the path tracer's: (relative RMSE ratio)^2 x (wall time ratio), < 1 where the
photon map wins. Prints the plan each photon-map run chose and its mean bias against the reference.

  scripts/heldout_check.py [--budget 8] [--seeds 1,2] [--vpm build/vpm | --vpm NAME=PATH,NAME=PATH]
                        [--reference-seconds 90] [--out out/heldout] SCENE.toml...

The error is over all RGB values, relative to the reference's mean."""
import argparse, json, os, subprocess, sys, time

ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
ap.add_argument('scenes', nargs='+')
ap.add_argument('--budget', type=float, default=8.0, help='render.time_limit of every compared run (seconds)')
ap.add_argument('--seeds', default='1,2')
ap.add_argument('--vpm', default='build/vpm', help='a binary, or NAME=PATH,... to compare binaries (the first also runs the path tracer)')
ap.add_argument('--reference-seconds', type=float, default=90.0)
ap.add_argument('--threads', type=int, default=2)
ap.add_argument('--integrators', default='photon_map,auto', help='the integrators compared with the path tracer (render.integrator values)')
ap.add_argument('--out', default='out/heldout')
a = ap.parse_args()
try:
    import numpy as np
except ImportError:
    sys.exit('heldout_check: needs numpy (apt-get install python3-numpy)')
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(a.vpm.split(',')[0].split('=')[-1])), 'python'))
try:
    import vpm
except ImportError:
    sys.exit('heldout_check: needs the vpm Python module beside the binary (build/python, built with the project)')
bins = [kv.split('=', 1) if '=' in kv else ['vpm', kv] for kv in a.vpm.split(',')]
os.makedirs(a.out, exist_ok=True)


def render(binary, scene, integrator, seed, seconds, out):
    t0 = time.monotonic()
    r = subprocess.run([binary, 'render', scene, '-q', '--threads', str(a.threads), '--set', f'render.integrator="{integrator}"',
                        '--set', f'render.seed={seed}', '--set', f'render.time_limit={seconds}', '-o', out], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f'heldout_check: {scene}: vpm failed: {r.stderr.strip().splitlines()[-1] if r.stderr.strip() else r.returncode}')
    wall = time.monotonic() - t0
    side = json.load(open(out[:-4] + '.json'))
    ag = side.get('photons', {}).get('auto_gather')
    # A plan without the map ("continue", the "auto" integrator's path tracer) makes no photon pass: its photon count means nothing.
    plan = '' if not ag else (f"{ag['chosen']} {ag['count']}x{ag['spp']}" if ag.get('photon_pass', True) else f"{ag['chosen']} x{ag['spp']}")
    if integrator == 'auto':
        plan = f"{side.get('integrator_used')}: {plan}"
    return np.asarray(vpm.read_exr(out), dtype=np.float64), wall, plan


for scene in a.scenes:
    name = os.path.splitext(os.path.basename(scene))[0]
    ref_path = os.path.join(a.out, f'ref-{name}.exr')
    if not os.path.exists(ref_path):
        print(f'{name}: rendering the reference (path tracer, {a.reference_seconds:g} s)', flush=True)
        render(bins[0][1], scene, 'path', 99, a.reference_seconds, ref_path)
    ref = np.asarray(vpm.read_exr(ref_path), dtype=np.float64)
    mean = ref.mean()
    for seed in a.seeds.split(','):
        img, wall, _ = render(bins[0][1], scene, 'path', seed, a.budget, os.path.join(a.out, f'{name}-path-{seed}.exr'))
        base = np.mean((img - ref) ** 2) / mean ** 2 * wall
        cols = []
        for label, binary in bins:
            for integrator in a.integrators.split(','):
                tag = label if integrator == 'photon_map' else f'{label} {integrator}'
                img, wall, plan = render(binary, scene, integrator, seed, a.budget,
                                         os.path.join(a.out, f'{name}-{label}-{integrator}-{seed}.exr'))
                ratio = np.mean((img - ref) ** 2) / mean ** 2 * wall / base
                cols.append(f'{tag} {ratio:.2f} ({plan}, bias {100 * (img.mean() - mean) / mean:+.1f}%)')
        print(f'{name} seed {seed}: ' + '  '.join(cols), flush=True)
