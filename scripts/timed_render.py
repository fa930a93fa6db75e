"""One photon-map render of a scene for the cost-model scripts (work_units_check.py, query_price_fit.py):
one thread, one pass, timed by the child's user CPU (getrusage), so that the machine's load mostly
does not enter. Returns (user CPU seconds, the run's sidecar); exits naming `who` and vpm's last
error line when vpm fails."""
import json, os, resource, subprocess, sys


def timed_render(vpm, scene, sets, tmp, who, quiet=False):
    out = os.path.join(tmp, 'run.exr')
    cmd = [vpm, 'render', scene, '--threads', '1'] + (['-q'] if quiet else []) + ['--set', f'render.output={out}']
    for s in ['render.integrator="photon_map"', 'render.passes=1'] + sets:
        cmd += ['--set', s]
    before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_utime
    r = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if r.returncode != 0:
        sys.exit(f'{who}: {os.path.basename(scene)[:-5]}: vpm failed: {r.stderr.strip().splitlines()[-1]}')
    return resource.getrusage(resource.RUSAGE_CHILDREN).ru_utime - before, json.load(open(out[:-4] + '.json'))
