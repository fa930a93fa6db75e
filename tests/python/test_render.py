"""vpm.render is `vpm render`: the same pixels for the same seed, the same files, the typed stats."""
import json
import os

import numpy as np

import vpm
from conftest import FURNACE, SMALL, run_tool, tool_overrides


def test_image_equals_the_tools_exr_byte_for_byte(vpm_binary, tmp_path):
    tool_exr = tmp_path / "tool.exr"
    code, err = run_tool(vpm_binary, "render", FURNACE, *tool_overrides(SMALL), "--threads", "2", "-q",
                         "-o", str(tool_exr))
    assert code == 0, err
    # A different thread count: a seed gives the same image on any thread count.
    result = vpm.render(vpm.load_config(FURNACE, overrides=SMALL), threads=1, progress=False)
    image = result.image
    assert image.dtype == np.float32 and image.shape == (16, 24, 3)
    assert image.tobytes() == vpm.read_exr(str(tool_exr)).tobytes()
    assert image.mean() > 0.1   # the furnace is lit (0.5 everywhere up to the estimator's noise)
    py_exr = tmp_path / "py.exr"
    result.save(str(py_exr))
    assert py_exr.read_bytes() == tool_exr.read_bytes()
    assert (tmp_path / "py.png").read_bytes() == (tmp_path / "tool.png").read_bytes()
    sidecar = json.loads((tmp_path / "py.json").read_text())
    tool_sidecar = json.loads((tmp_path / "tool.json").read_text())
    # The same resolved config but for what the command line set (-o, --threads).
    for config in (sidecar["config"], tool_sidecar["config"]):
        assert config["render"].pop("output").endswith(".exr")
        config["render"].pop("threads")
    assert sidecar["config"] == tool_sidecar["config"]
    assert sidecar["photons"]["stored"] == tool_sidecar["photons"]["stored"]


def test_image_is_a_view_on_the_result_not_a_copy():
    result = vpm.render(vpm.load_config(FURNACE, overrides=SMALL), progress=False)
    a, b = result.image, result.image
    assert not a.flags.owndata and np.shares_memory(a, b)
    del result   # the arrays keep the pixels alive
    assert np.isfinite(a).all()


def test_stats_are_the_typed_run_stats():
    # The photon map with its defaults estimates from its map (only render.integrator = "auto" may go without it).
    result = vpm.render(vpm.load_config(FURNACE, overrides=SMALL), progress=False)
    stats = result.stats
    assert set(stats["phases"]) >= {"trace", "build", "render"}
    assert stats["photons"]["emitted"] == SMALL["photons.count"]
    assert stats["photons"]["stored"] > 0
    assert stats["render"]["samples"] == 24 * 16 * 2
    # Every camera-ray collision in the furnace takes the estimator proper (rule counts).
    assert stats["photons"]["estimate_cases"]["knn"] > 0
    assert stats["passes"]["count"] == 1
    assert result.record["seed"] == 7


def test_save_refuses_a_non_exr_output_with_the_tools_message(tmp_path):
    result = vpm.render(vpm.load_config(FURNACE, overrides=SMALL), progress=False)
    try:
        result.save(str(tmp_path / "img.png"))
    except vpm.FileError as e:
        assert ".exr" in str(e)
    else:
        raise AssertionError("save to .png did not raise")
    assert not any(tmp_path.iterdir())   # nothing written


def test_result_says_what_ran_and_how_long():
    result = vpm.render(vpm.load_config(FURNACE, overrides=SMALL), progress=False)
    stats = result.stats
    assert result.integrator_used == stats["integrator_used"] == "photon_map"
    assert result.gather_used == stats["gather_used"] and result.gather_used != "none"
    assert result.map_estimates == stats["map_estimates"] > 0
    assert result.photons_traced == sum(stats["photons"]["traced"][k] for k in
                                        ("pass_maps", "pilot_only", "probe", "decision_map")) > 0
    assert result.passes == stats["passes"]["count"] and result.spp_per_pass == stats["passes"]["spp_per_pass"]
    phases = sum(p["seconds"] for p in stats["phases"].values())
    assert result.seconds >= 0.9 * phases > 0
    assert "photon_map" in repr(result)
    path = vpm.render(vpm.load_config(FURNACE, overrides=dict(SMALL, **{"render.integrator": "path"})), progress=False)
    assert path.integrator_used == "path" and path.gather_used == "none" and path.map_estimates == 0
    assert path.photons_traced == 0


def test_warnings_of_a_limit_the_pins_cannot_fit_are_in_the_stats():
    # A pinned photons.count and a limit far below one pass: both said in result.stats["warnings"],
    # as in the sidecar and the log.
    config = vpm.load_config(FURNACE, overrides=["render.width=4", "render.height=4", "render.spp=1",
                                                 "render.passes=1", "photons.count=20000",
                                                 'photons.gather="collision"', "render.time_limit=1e-6"])
    warnings = vpm.render(config, progress=False).stats["warnings"]
    assert any("photons.count = 20000 is set" in w for w in warnings), warnings
    assert any("is shorter than the first pass" in w for w in warnings), warnings
