"""Error against time for both integrators on the default scene (smoke plume on a floor).

A path-traced reference first, then equal-time runs (render.time_limit: passes until the budget)
of the photon map and the path tracer, each compared with it by relative RMSE (sweeps' metric).
Run from the repository root: build/vpm-python examples/error_vs_time.py [reference spp]
"""
import sys

import numpy as np

import vpm

SIZE = {"render.width": 64, "render.height": 64}
LUMINANCE = np.array([0.2126, 0.7152, 0.0722])


def rel_rmse(image, reference):
    """RMSE of the luminance over the reference's mean luminance (README, "Metrics")."""
    y, y_ref = image @ LUMINANCE, reference @ LUMINANCE
    return np.sqrt(np.mean((y - y_ref) ** 2)) / y_ref.mean()


reference_spp = int(sys.argv[1]) if len(sys.argv) > 1 else 1024
reference = vpm.render(vpm.load_config("configs/default.toml", overrides=dict(SIZE, **{
    "render.spp": reference_spp, "render.seed": 1000})), progress=False).image
print(f"reference: path tracer, {reference_spp} spp")
print("budget_s  method       passes  seconds  rel_rmse")
for budget in [1.0, 2.0, 4.0, 8.0]:   # a run takes at least one pass (one photon pass)
    for name, path in [("photon_map", "configs/default_photon_map.toml"), ("path", "configs/default.toml")]:
        config = vpm.load_config(path, overrides=dict(SIZE, **{"render.spp": 4, "render.time_limit": budget}))
        result = vpm.render(config, progress=False)
        seconds = sum(p["seconds"] for p in result.stats["phases"].values())
        passes = result.stats["passes"]["count"]
        print(f"{budget:8.1f}  {name:11s} {passes:6d} {seconds:8.2f}  {rel_rmse(result.image, reference):.4f}")
