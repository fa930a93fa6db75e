"""vpm.compare and vpm.luminance: the sweep's metrics from Python, the samples warning."""
import json
import math
import os
import subprocess

import numpy as np
import pytest

import vpm
from conftest import FURNACE, SMALL, SOURCE_DIR


def flat(v, shape=(6, 8)):
    return np.full(shape + (3,), v, dtype=np.float32)


def test_one_image_and_repeats_against_a_reference():
    one = vpm.compare(flat(0.55), flat(0.5))
    assert one["repeats"] == 1
    assert one["rel_bias"] == pytest.approx(0.1, abs=1e-6) and one["rel_rmse"] == pytest.approx(0.1, abs=1e-6)
    assert math.isnan(one["rel_bias_se"]) and math.isnan(one["rel_variance"])
    assert one["reference_luminance"] == pytest.approx(0.5, abs=1e-6)
    two = vpm.compare([flat(0.55), flat(0.45)], flat(0.5))
    assert two["repeats"] == 2 and len(two["images"]) == 2
    assert two["rel_bias"] == pytest.approx(0.0, abs=1e-6) and two["rel_bias_se"] == pytest.approx(0.1, abs=1e-6)
    assert two["rel_mse"] == pytest.approx(two["rel_bias2"] + two["rel_variance"], abs=1e-9)
    assert two["images"][1]["rel_bias"] == pytest.approx(-0.1, abs=1e-6)
    with pytest.raises(vpm.Error, match="reference is 8x6"):
        vpm.compare(flat(0.5, (4, 4)), flat(0.5))


def test_luminance_weights():
    image = np.zeros((1, 3, 3), dtype=np.float32)
    image[0, 0, 0] = image[0, 1, 1] = image[0, 2, 2] = 1.0
    assert vpm.luminance(image)[0].tolist() == pytest.approx([0.2126, 0.7152, 0.0722], abs=1e-6)


def test_render_results_and_files_match_the_tool_and_warn_on_samples(vpm_binary, tmp_path):
    config = vpm.load_config(FURNACE, overrides=SMALL)
    run = vpm.render(config, progress=False)
    reference = vpm.render(vpm.load_config(FURNACE, overrides=dict(SMALL, **{"render.integrator": "path",
                                                                             "render.spp": 1})), progress=False)
    with pytest.warns(UserWarning, match="more than the"):
        result = vpm.compare(run, reference)
    assert result["samples"] == run.stats["render"]["samples"] > result["reference_samples"]
    assert len(result["warnings"]) == 1
    run.save(str(tmp_path / "run.exr"))
    reference.save(str(tmp_path / "ref.exr"))
    with pytest.warns(UserWarning):
        from_files = vpm.compare(tmp_path / "run.exr", str(tmp_path / "ref.exr"))
    tool = subprocess.run([vpm_binary, "compare", "--json", str(tmp_path / "run.exr"), str(tmp_path / "ref.exr")],
                          capture_output=True, text=True)
    assert tool.returncode == 0 and "more than the" in tool.stderr
    tool_json = json.loads(tool.stdout)
    assert from_files["rel_rmse"] == pytest.approx(tool_json["luminance_rel_rmse"], rel=1e-5)
    assert from_files["rel_bias"] == pytest.approx(tool_json["luminance_rel_bias"], rel=1e-5, abs=1e-9)
    assert from_files["rel_rmse"] == pytest.approx(result["rel_rmse"], rel=1e-6)


def test_info_of_a_config_and_a_vdb():
    import os
    from conftest import SOURCE_DIR
    scene = vpm.info(FURNACE, overrides={"render.width": 16})
    assert scene["kind"] == "scene" and scene["media"] and scene["image"]["width"] == 16
    seen = scene["camera"]["seen"]
    assert abs(seen["medium"] + seen["surface_only"] + seen["nothing"] - 1) < 1e-12
    grid = vpm.info(os.path.join(SOURCE_DIR, "media", "plume.vdb"))
    assert grid["kind"] == "vdb" and grid["grids"][0]["active_voxels"] > 0
    with pytest.raises(vpm.Error):
        vpm.info(os.path.join(SOURCE_DIR, "media", "plume.vdb"), overrides={"photons.k": 4})


def test_named_metric_mask_and_reference_noise(tmp_path):
    ref, img = flat(0.5), flat(0.55)
    ref[0, 0] = 100.0   # a glint the image gets half right
    img[0, 0] = 50.0
    out = vpm.compare(img, ref)
    assert out["metric"] == "relMSE" and "(R^2 + 0.01)" in out["metric_formula"]
    per_pixel = 0.05 ** 2 / (0.25 + 0.01)
    assert out["error"] == pytest.approx((47 * per_pixel + 2500 / 10000.01) / 48, rel=1e-5)
    assert math.isnan(out["noise_floor"]) and math.isnan(out["error_se"])
    masked = vpm.compare(img, ref, metric="relrmse", exclude=[(0, 0, 1, 1)])
    assert masked["error"] == pytest.approx(0.1, rel=1e-5) and masked["pixels"] == 47
    mask = np.ones((6, 8), dtype=np.float32)
    mask[0, 0] = 0
    assert vpm.compare(img, ref, metric="smape", mask=mask)["error"] == pytest.approx(0.05 / 1.06, rel=1e-5)
    # The noise floor: from a variance array, from REF.variance.exr beside a reference file, from halves.
    var = np.full((6, 8, 3), 0.0013, dtype=np.float32)
    with_var = vpm.compare(img, ref, crop=(1, 0, 8, 6), reference_variance=var)
    assert with_var["noise_floor"] == pytest.approx(0.0013 / 0.26, rel=1e-5)
    assert with_var["error"] == pytest.approx(per_pixel - 0.0013 / 0.26, rel=1e-4)
    halves = vpm.compare(img, (flat(0.4), flat(0.6)), crop=(1, 0, 8, 6))
    assert halves["noise_floor"] == pytest.approx(0.01 / 0.26, rel=1e-5)
    with pytest.raises(vpm.Error, match="allowed: relmse, relrmse, smape"):
        vpm.compare(img, ref, metric="psnr")
    with pytest.raises(vpm.Error, match="crop"):
        vpm.compare(img, ref, crop=(3, 3, 1, 1))


def test_exclude_lights_mask_leaves_out_the_pixels_that_see_an_area_light():
    # configs/glass_sphere_fog.toml with its sphere light moved into view and the glass out of it:
    # a disc of about 2.7 pixels in radius at 64x64 (tests/analysis/metrics/seen_lights_test.cpp).
    glass = os.path.join(SOURCE_DIR, "configs", "glass_sphere_fog.toml")
    config = vpm.load_config(glass, overrides={"render.width": 64, "render.height": 64, "lights.0.center": [0.0, 0.5, 1.0],
                                               "lights.0.radius": 0.1, "shapes.0.center": [0.0, 50.0, 0.0]})
    mask = vpm.exclude_lights_mask(config)
    assert mask.shape == (64, 64) and set(np.unique(mask)) <= {0.0, 1.0}
    seen = int((mask == 0).sum())
    assert 16 <= seen <= 60
    assert vpm.exclude_lights_mask(config, width=32, height=32).shape == (32, 32)
    # As vpm.compare's mask: the seen pixels are left out.
    ref, img = np.full((64, 64, 3), 0.5, dtype=np.float32), np.full((64, 64, 3), 0.5, dtype=np.float32)
    img[mask == 0] = 100.0
    out = vpm.compare(img, ref, mask=mask)
    assert out["pixels"] == 64 * 64 - seen and out["error"] == 0.0
    with pytest.raises(vpm.Error, match="aspect ratio"):
        vpm.exclude_lights_mask(config, width=64, height=32)
