"""A histogram of kNN radii in the dense sphere, in mean free paths.

configs/homogeneous.toml's sphere (radius 1) made dense (sigma_t_scale 1000: a mean free path of
1 mm): the photons sit in a skin under the lit side, so kNN balls deep inside are many mean free
paths wide (docs/dense_media.md). Run from the repository root: build/vpm-python examples/knn_radii.py
"""
import numpy as np

import vpm

SIGMA_T = 1000.0
config = vpm.load_config("configs/homogeneous.toml", overrides={
    "render.integrator": "photon_map", "media.0.sigma_t_scale": SIGMA_T, "photons.count": 100000})
photons = vpm.trace_photons(config)
print(f"{len(photons)} photons stored; mean distance from the centre {np.linalg.norm(photons.positions, axis=1).mean():.3f}")

rng = np.random.default_rng(1)
points = rng.normal(size=(20000, 3))
points *= (rng.uniform(size=(20000, 1)) ** (1 / 3)) / np.linalg.norm(points, axis=1, keepdims=True)   # uniform in the ball
distances, _ = photons.knn(points, k=32)
radii_mfp = distances[:, -1] * SIGMA_T
counts, edges = np.histogram(np.log10(radii_mfp), bins=12)
print("r_32 in mean free paths (log-spaced bins), points uniform in the sphere:")
for c, lo, hi in zip(counts, edges[:-1], edges[1:]):
    print(f"  {10 ** lo:9.2f} .. {10 ** hi:9.2f}  {'#' * int(60 * c / counts.max()):60s} {c}")
