"""The k vs k-1 bias curve on the furnace: classic is high by 1/(k-1), corrected is unbiased.

In configs/uniform_furnace.toml the radiance is 0.5 everywhere, so the image mean over 0.5 is
1 + the estimator's relative bias. Run from the repository root: python3 examples/bias_vs_k.py
"""
import vpm

for k in [3, 4, 6, 8, 16, 32]:
    bias = {}
    for estimator in ["classic", "corrected"]:
        config = vpm.load_config("configs/uniform_furnace.toml", overrides={
            "photons.k": k, "photons.estimator": estimator, "render.width": 32, "render.height": 32})
        bias[estimator] = vpm.render(config, progress=False).image.mean() / 0.5 - 1
    print(f"k={k:3d}  classic {bias['classic']:+.4f} (theory {1 / (k - 1):+.4f})  corrected {bias['corrected']:+.4f}")
