"""Inputs nobody designed (issue 61): each one a vpm.Error naming the argument and what is allowed,
never RecursionError, a pybind TypeError, a silent infinity, a NaN answer or a silently smaller k."""
import math

import numpy as np
import pytest

import vpm
from conftest import FURNACE, SMALL


def test_cyclic_and_deep_dicts_are_config_errors():
    cyclic = {"render": {"width": 8}}
    cyclic["render"]["self"] = cyclic
    with pytest.raises(vpm.ConfigError, match="render.self: the value contains itself"):
        vpm.load_config(cyclic)
    looped = [1]
    looped.append(looped)
    with pytest.raises(vpm.ConfigError, match="contains itself"):
        vpm.load_config({"camera": {"position": looped}})
    deep = {}
    node = deep
    for _ in range(200):
        node["a"] = {}
        node = node["a"]
    with pytest.raises(vpm.ConfigError, match="nesting deeper than 64"):
        vpm.load_config(deep)


def test_compare_refuses_nan_images_and_values_beyond_float32():
    reference = np.full((4, 4, 3), 0.5)
    with pytest.raises(vpm.Error, match="image 0: 16 of 16 pixels are NaN or Inf"):
        vpm.compare(np.full((4, 4, 3), np.nan), reference)
    huge = reference.copy()
    huge[1, 2, 0] = 1e308
    with pytest.raises(vpm.Error, match=r"image 0: value .* at \[1, 2, 0\] is beyond float32"):
        vpm.compare(huge, reference)
    with pytest.raises(vpm.Error, match="reference: value"):
        vpm.compare(reference, huge)
    assert vpm.compare(reference, reference)["rel_rmse"] == 0.0
    assert math.isnan(vpm.luminance(np.full((1, 1, 3), np.nan))[0, 0])   # luminance keeps NaN as NaN


def test_photon_map_refuses_values_its_records_cannot_hold():
    good = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
    powers = np.ones((2, 3))
    dirs = np.tile([0.0, 0.0, 1.0], (2, 1))
    with pytest.raises(vpm.Error, match=r"positions\[1\].*within \+-1e38"):
        vpm.PhotonMap(np.array([[0.0, 0.0, 0.0], [1e308, 0.0, 0.0]]), powers, dirs)
    with pytest.raises(vpm.Error, match=r"powers\[0\].*not finite"):
        vpm.PhotonMap(good, np.array([[np.inf, 1.0, 1.0], [1.0, 1.0, 1.0]]), dirs)


def test_estimate_refuses_k_above_the_photon_count():
    rng = np.random.default_rng(5)
    m = vpm.PhotonMap(rng.uniform(-1, 1, (10, 3)), np.ones((10, 3)), np.tile([0.0, 0.0, 1.0], (10, 1)))
    p = np.zeros((1, 3))
    wo = np.array([[0.0, 0.0, 1.0]])
    with pytest.raises(vpm.Error, match="k = 100 but the map holds 10 photons; k must be at most 10"):
        m.estimate(p, wo, k=100, g=0.0)
    assert m.estimate(p, wo, k=10, g=0.0, estimator="classic").shape == (1, 3)


def test_wrong_argument_types_are_vpm_errors():
    m = vpm.PhotonMap(np.zeros((4, 3)), np.ones((4, 3)), np.tile([0.0, 0.0, 1.0], (4, 1)))
    with pytest.raises(vpm.Error, match="PhotonMap.knn: arguments of the wrong type; accepted: .*k: int"):
        m.knn(np.zeros((1, 3)), k="eight")
    with pytest.raises(vpm.Error, match="PhotonMap: arguments of the wrong type"):
        vpm.PhotonMap(np.zeros((4, 3)), np.ones((4, 3)), np.tile([0.0, 0.0, 1.0], (4, 1)), leaf_size="big")
    config = vpm.load_config(FURNACE, overrides=SMALL)
    with pytest.raises(vpm.Error, match="render: arguments of the wrong type"):
        vpm.render(config, threads="two")
    with pytest.raises(vpm.Error, match="trace_photons: arguments of the wrong type"):
        vpm.trace_photons(config, stream_offset="one")
    with pytest.raises(vpm.Error, match="read_exr: arguments of the wrong type"):
        vpm.read_exr(3.5)
