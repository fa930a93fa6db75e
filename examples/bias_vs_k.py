"""The k vs k-1 bias curve on the furnace: classic over corrected is k/(k-1).

In configs/uniform_furnace.toml the radiance is 0.5 everywhere, so the image mean over 0.5 is
1 + the estimator's relative bias. Both estimators also share an offset that shrinks with k: the
photons of one random walk are correlated, not Poisson (the study's photon_pass scenario).
Run from the repository root: build/vpm-python examples/bias_vs_k.py
"""
import vpm

for k in [3, 4, 6, 8, 16, 32]:
    mean = {}
    for estimator in ["classic", "corrected"]:
        config = vpm.load_config("configs/uniform_furnace.toml", overrides={
            "photons.k": k, "photons.estimator": estimator, "render.width": 32, "render.height": 32})
        mean[estimator] = vpm.render(config, progress=False).image.mean() / 0.5
    print(f"k={k:3d}  bias: classic {mean['classic'] - 1:+.4f}, corrected {mean['corrected'] - 1:+.4f};"
          f"  classic/corrected {mean['classic'] / mean['corrected']:.4f} (k/(k-1) = {k / (k - 1):.4f})")
