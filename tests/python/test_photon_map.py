"""vpm.trace_photons and vpm.PhotonMap: the render's photons, exact kNN, unbiased corrected estimates."""
import json
import math

import numpy as np
import pytest

import vpm
from conftest import FURNACE, SMALL, run_tool, tool_overrides


def test_arrays_have_the_sidecars_counts(vpm_binary, tmp_path):
    code, err = run_tool(vpm_binary, "render", FURNACE, *tool_overrides(SMALL), "-q", "-o", str(tmp_path / "t.exr"))
    assert code == 0, err
    sidecar = json.loads((tmp_path / "t.json").read_text())
    photons = vpm.trace_photons(vpm.load_config(FURNACE, overrides=SMALL))
    n = sidecar["photons"]["stored"]
    assert n > 1000 and len(photons) == n
    for a in (photons.positions, photons.powers, photons.directions):
        assert a.shape == (n, 3) and a.dtype == np.float64
    assert photons.stats["photons"]["stored"] == n
    assert photons.stats["photons"]["emitted"] == sidecar["photons"]["emitted"]
    assert photons.surface is None   # no shapes in the furnace
    assert np.allclose(np.linalg.norm(photons.directions, axis=1), 1.0, atol=1e-3)
    # Every photon lies in the medium, a sphere of radius 6 around the origin.
    assert np.linalg.norm(photons.positions, axis=1).max() <= 6.0 + 1e-6


def test_knn_matches_brute_force():
    photons = vpm.trace_photons(vpm.load_config(FURNACE, overrides=SMALL))
    positions = photons.positions
    rng = np.random.default_rng(3)
    points = rng.uniform(-4, 4, size=(200, 3))
    k = 10
    distances, indices = photons.knn(points, k)
    assert distances.shape == (200, k) and indices.shape == (200, k)
    d2 = ((points[:, None, :] - positions[None, :, :]) ** 2).sum(axis=2)
    order = np.argsort(d2, axis=1, kind="stable")[:, :k]
    assert np.array_equal(indices, order)
    assert np.allclose(distances, np.sqrt(np.take_along_axis(d2, order, axis=1)), rtol=1e-12, atol=0)
    # A radius limit: neighbours beyond it are missing (inf, -1).
    r = float(np.median(distances[:, 4]))
    d_lim, i_lim = photons.knn(points, k, max_radius=r)
    inside = distances <= r
    assert np.array_equal(i_lim[inside], indices[inside]) and (i_lim[~inside] == -1).all()
    assert np.isinf(d_lim[~inside]).all()


def uniform_map(n, rng):
    """n photons uniform in the unit cube, power 1, isotropic directions: density n, S = n / (4 pi)."""
    directions = rng.normal(size=(n, 3))
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    return vpm.PhotonMap(rng.uniform(0, 1, size=(n, 3)), np.ones((n, 3)), directions)


def test_corrected_estimate_is_unbiased_in_the_uniform_case():
    # Independent maps, each queried on a 3x3x3 grid of interior points 0.25 apart: the kNN balls
    # (r ~ 0.06 at k = 16, n = 20000) are disjoint and inside the cube, so the estimates are
    # independent; the truth is n / (4 pi) for g = 0 (isotropic phase function, unit powers).
    n, k, maps = 20000, 16, 20
    grid = np.stack(np.meshgrid(*[[0.25, 0.5, 0.75]] * 3, indexing="ij"), axis=-1).reshape(-1, 3)
    rng = np.random.default_rng(20130619)
    wo = np.tile([0.0, 0.0, 1.0], (len(grid), 1))
    corrected, classic = [], []
    for _ in range(maps):
        m = uniform_map(n, rng)
        values, radii = m.estimate(grid, wo, estimator="corrected", k=k, g=0.0, return_radius=True)
        assert radii.max() < 0.12   # the balls stay disjoint and inside the cube
        corrected.append(values[:, 0])
        classic.append(m.estimate(grid, wo, estimator="classic", k=k, g=0.0)[:, 0])
    truth = n / (4 * math.pi)
    e = np.concatenate(corrected) / truth
    se = e.std(ddof=1) / math.sqrt(len(e))
    assert abs(e.mean() - 1.0) < 4 * se, (e.mean(), se)
    # ... while classic is high by 1/(k-1) (6.7%, about 6 standard errors here).
    c = np.concatenate(classic) / truth
    assert c.mean() - 1.0 > 2 * se
    assert abs((c.mean() - 1.0) - 1.0 / (k - 1)) < 4 * se


def test_estimate_defaults_come_from_the_config():
    config = vpm.load_config(FURNACE, overrides=dict(SMALL, **{"photons.k": 8}))
    photons = vpm.trace_photons(config)
    points = np.zeros((4, 3))
    wo = np.tile([0.0, 0.0, 1.0], (4, 1))
    explicit = photons.estimate(points, wo, estimator="corrected", k=8, g=0.3)   # the config's values
    assert np.array_equal(photons.estimate(points, wo), explicit)
    assert not np.array_equal(photons.estimate(points, wo, k=16), explicit)


def test_bad_estimate_arguments_raise_with_the_message():
    m = uniform_map(1000, np.random.default_rng(1))
    p = np.full((1, 3), 0.5)
    wo = np.array([[0.0, 0.0, 1.0]])
    with pytest.raises(vpm.Error, match="classic, corrected, mse_optimal"):
        m.estimate(p, wo, estimator="best", k=8, g=0.0)
    with pytest.raises(vpm.Error, match="k"):
        m.estimate(p, wo, estimator="corrected", k=1, g=0.0)
    with pytest.raises(vpm.Error, match="no scene media"):
        m.estimate(p, wo, k=8)
    with pytest.raises(vpm.Error, match=r"shape \(n, 3\)"):
        m.knn(np.zeros((3, 2)), 4)


def test_estimate_at_a_pass_follows_the_schedule():
    # photons.schedule = "progressive" (docs/progressive.md): pass_index takes that pass's k and radius
    # scale; the ball counted in shrinks, and pass 0 is the plain estimate.
    config = vpm.load_config(FURNACE, overrides=dict(SMALL, **{"photons.k": 16, "photons.schedule": "progressive"}))
    photons = vpm.trace_photons(config)
    points = np.zeros((4, 3))
    wo = np.tile([0.0, 0.0, 1.0], (4, 1))
    plain, r0 = photons.estimate(points, wo, return_radius=True)
    first, r_first = photons.estimate(points, wo, return_radius=True, pass_index=0)
    assert np.array_equal(first, plain) and np.array_equal(r_first, r0)
    _, r_late = photons.estimate(points, wo, return_radius=True, pass_index=100)
    assert (r_late < 0.8 * r0).all()
    with pytest.raises(vpm.Error, match="pass_index"):
        photons.estimate(points, wo, pass_index=-1)


def test_estimate_and_knn_refuse_what_the_constructor_refuses():
    m = uniform_map(1000, np.random.default_rng(2))
    p = np.full((2, 3), 0.5)
    good = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])
    for bad in ([0.0, 0.0, 0.0], [math.nan, 0.0, 1.0], [0.0, 0.0, 2.0]):
        with pytest.raises(vpm.Error, match=r"estimate: directions\[1\] has length"):
            m.estimate(p, np.array([good[0], bad]), k=8, g=0.0)
    nan_point = np.array([[0.5, 0.5, 0.5], [math.nan, 0.5, 0.5]])
    with pytest.raises(vpm.Error, match=r"estimate: points\[1\] is not finite"):
        m.estimate(nan_point, good, k=8, g=0.0)
    with pytest.raises(vpm.Error, match=r"knn: points\[1\] is not finite"):
        m.knn(nan_point, 4)


def test_integer_arguments_out_of_range_are_one_clear_error():
    # Negative, zero or huge ints: vpm.Error naming the argument and its range (not pybind's
    # TypeError, not a leaf size of 0 clamped to 1, not k wrapped to int in a pass's schedule).
    m = uniform_map(1000, np.random.default_rng(5))
    p = np.full((1, 3), 0.5)
    d = np.array([[0.0, 0.0, 1.0]])
    for k in (0, -1, 2 ** 40):
        with pytest.raises(vpm.Error, match=r"estimate: k must be in \[1, 1048576\]"):
            m.estimate(p, d, k=k, g=0.0)
        with pytest.raises(vpm.Error, match=r"knn: k must be in \[1, 1048576\]"):
            m.knn(p, k)
    with pytest.raises(vpm.Error, match=r"pass_index must be in \[0, 2147483647\]"):
        m.estimate(p, d, k=8, g=0.0, pass_index=2 ** 40)
    for leaf in (0, -1):
        with pytest.raises(vpm.Error, match=r"leaf_size must be in \[1, "):
            vpm.PhotonMap(m.positions, m.powers, m.directions, leaf_size=leaf)
    # knn's (m, k) results beyond half the memory: refused before the allocation.
    with pytest.raises(vpm.Error, match=r"knn: .* GB of results"):
        m.knn(np.broadcast_to(p, (10 ** 7, 3)), 2 ** 20)


def test_negative_powers_are_refused():
    rng = np.random.default_rng(4)
    n = 100
    directions = np.tile([0.0, 0.0, 1.0], (n, 1))
    powers = np.ones((n, 3))
    powers[17, 1] = -1e-3
    with pytest.raises(vpm.Error, match="photon 17 has negative power"):
        vpm.PhotonMap(rng.uniform(size=(n, 3)), powers, directions)


def test_a_map_beyond_half_the_memory_is_refused_before_any_allocation():
    # Broadcast views: 1e11 rows that take no memory, so only the guard can stop the build.
    n = 10 ** 11
    rows = lambda v: np.broadcast_to(np.array([v], dtype=np.float64), (n, 3))
    with pytest.raises(vpm.Error, match=r"photons fit"):
        vpm.PhotonMap(rows([0.5, 0.5, 0.5]), rows([1.0, 1.0, 1.0]), rows([0.0, 0.0, 1.0]))


def test_threads_beyond_the_tools_range_are_refused():
    config = vpm.load_config(FURNACE, overrides=SMALL)
    for threads in (-1, 5000, 10 ** 9):
        with pytest.raises(vpm.Error, match="threads: expected 0 .* to 4096"):
            vpm.trace_photons(config, threads=threads)
        with pytest.raises(vpm.Error, match="threads: expected 0 .* to 4096"):
            vpm.render(config, threads=threads)


def test_walk_labels_of_a_map_from_arrays():
    rng = np.random.default_rng(56)
    n = 600
    positions, directions = rng.uniform(0, 1, size=(n, 3)), np.tile([0.0, 0.0, 1.0], (n, 1))
    # None: every photon its own walk
    assert len(set(vpm.PhotonMap(positions, np.ones((n, 3)), directions).walks.tolist())) == n
    labels = 5 * (np.arange(n) // 3) + 11   # walks of three photons, labels with gaps
    m = vpm.PhotonMap(positions, np.ones((n, 3)), directions, walks=labels)
    walks = m.walks
    assert walks.shape == (n,) and walks.dtype == np.int64 and sorted(set(walks.tolist())) == list(range(n // 3))
    # stored order: each stored photon's input row is the nearest input position
    rows = np.argmin(((m.positions[:, None, :] - positions[None, :, :]) ** 2).sum(axis=2), axis=1)
    assert len(set(rows.tolist())) == n
    for a in range(0, n, 7):
        for b in range(0, n, 11):
            assert (walks[a] == walks[b]) == (labels[rows[a]] == labels[rows[b]])
    for bad, message in (([1] * (n - 1), r"shape \(600,\)"), (np.full(n, 1.5), "integer"),
                         (np.arange(n) - 1, r"walks\[0\] = -1")):
        with pytest.raises(vpm.Error, match=message):
            vpm.PhotonMap(positions, np.ones((n, 3)), directions, walks=bad)


def test_walk_neighbours_from_python():
    # Walks of two photons 1e-3 apart: the walk-corrected estimate is unbiased for the photon density
    # (docs/walk_correlation.md), the photon-neighbour one reads high; with every photon its own walk
    # the walk form is the photon form.
    n, k, maps = 20000, 16, 20
    grid = np.stack(np.meshgrid(*[[0.25, 0.5, 0.75]] * 3, indexing="ij"), axis=-1).reshape(-1, 3)
    wo = np.tile([0.0, 0.0, 1.0], (len(grid), 1))
    rng = np.random.default_rng(5656)
    walk_form, photon_form = [], []
    for _ in range(maps):
        first = rng.uniform(0, 1, size=(n // 2, 3))
        step = rng.normal(size=(n // 2, 3))
        step *= 1e-3 / np.linalg.norm(step, axis=1, keepdims=True)
        positions = np.concatenate([first, first + step])
        directions = rng.normal(size=(n, 3))
        directions /= np.linalg.norm(directions, axis=1, keepdims=True)
        labels = np.concatenate([np.arange(n // 2), np.arange(n // 2)])
        m = vpm.PhotonMap(positions, np.ones((n, 3)), directions, walks=labels)
        walk_form.append(m.estimate(grid, wo, estimator="corrected", k=k, g=0.0, neighbours="walks")[:, 0])
        photon_form.append(m.estimate(grid, wo, estimator="corrected", k=k, g=0.0, neighbours="photons")[:, 0])
    truth = n / (4 * math.pi)
    w, p = np.concatenate(walk_form) / truth, np.concatenate(photon_form) / truth
    se_w, se_p = w.std(ddof=1) / math.sqrt(len(w)), p.std(ddof=1) / math.sqrt(len(p))
    assert abs(w.mean() - 1.0) < 4 * se_w, (w.mean(), se_w)
    assert p.mean() - 1.0 > 4 * se_p, (p.mean(), se_p)
    single = uniform_map(2000, rng)
    points = rng.uniform(0.2, 0.8, size=(50, 3))
    wo = np.tile([0.0, 0.0, 1.0], (50, 1))
    assert np.array_equal(single.estimate(points, wo, estimator="corrected", k=8, g=0.0, neighbours="walks"),
                          single.estimate(points, wo, estimator="corrected", k=8, g=0.0))
    with pytest.raises(vpm.Error, match="allowed"):
        single.estimate(points, wo, k=8, g=0.0, neighbours="paths")
    with pytest.raises(vpm.Error, match="no walk form"):
        single.estimate(points, wo, estimator="mse_optimal", k=8, g=0.0, neighbours="walks")


def test_estimate_honours_the_configs_neighbours():
    config = vpm.load_config(FURNACE, overrides=dict(SMALL, **{"photons.k": 8, "photons.neighbours": "walks"}))
    photons = vpm.trace_photons(config)
    assert len(set(photons.walks.tolist())) < len(photons)   # the tracer's walks: several photons each
    points = np.zeros((4, 3))
    wo = np.tile([0.0, 0.0, 1.0], (4, 1))
    walks = photons.estimate(points, wo, neighbours="walks")
    assert np.array_equal(photons.estimate(points, wo), walks)
    assert not np.array_equal(photons.estimate(points, wo, neighbours="photons"), walks)
