#!/bin/bash
# MIS on vs off at equal samples on configs/small_light_smoke.toml (docs/studies/area_lights_mis.md section 9), from the
# repository root: bench/mis_error.sh NAME [--set KEY=VALUE]...
# A 64x64 reference at 16384 spp (MIS on, seed 4242), then 8 seeds x 64 spp per mode, each against it
# with vpm compare; prints the relative RMSE per run, their median and root mean square.
set -e
name=$1; shift
V=${VPM:-./build/vpm}; C=configs/small_light_smoke.toml; D=${OUT:-out/mis_bench}/$name; mkdir -p $D
common="--set render.width=64 --set render.height=64"
/usr/bin/time -f "ref %e s" $V render $C -o $D/ref.exr $common --set render.spp=16384 --set render.seed=4242 -q "$@"
for mis in true false; do for s in 1 2 3 4 5 6 7 8; do
  $V render $C -o $D/${mis}_$s.exr $common --set render.spp=64 --set render.seed=$s --set render.mis=$mis -q "$@"
  $V compare --json $D/${mis}_$s.exr $D/ref.exr; echo
done; done > $D/rows.txt
python3 - $D <<'PY'
import json,statistics as st,sys
D=sys.argv[1]
rows=[json.loads(l) for l in open(D+'/rows.txt') if l.strip()]
for mode in ('true','false'):
    r=[x for x in rows if f'/{mode}_' in x['image']]
    rr=[x['relative_rmse'] for x in r]; mb=[x['relative_bias'] for x in r]
    t=[json.load(open(x['image'][:-4]+'.json'))['phases']['render']['seconds'] for x in r]
    print(D, 'mis', mode, ' '.join(f'{v:.3f}' for v in rr), 'median',f'{st.median(rr):.3f}','rms',f'{(sum(v*v for v in rr)/len(rr))**.5:.3f}', 'mean bias', f'{st.mean(mb):+.4f}', 'render s median', f'{st.median(t):.3f}')
PY
