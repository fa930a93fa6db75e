"""vpm.load_config validates like the tool: the same messages for bad overrides and bad files."""
import os

import pytest

import vpm
from conftest import FURNACE, run_tool


def tool_error(binary, *args):
    """The message `vpm render` prints after "error: " (its one line), with the exit code."""
    code, err = run_tool(binary, "render", *args, "-q", "-o", os.devnull + ".exr")
    line = [l for l in err.splitlines() if ": error: " in l]
    assert code == 1 and len(line) == 1, err
    return line[0].split(": error: ", 1)[1]


@pytest.mark.parametrize("key, value", [
    ("photons.k", "many"),                  # wrong type
    ("photons.estimator", "best"),          # not an allowed name
    ("photons.kk", 8),                      # unknown key
    ("media.3.g", 0.5),                     # no such array entry
    ("render.spp", -4),                     # out of range
])
def test_overrides_validate_like_set(vpm_binary, key, value):
    with pytest.raises(vpm.ConfigError) as raised:
        vpm.load_config(FURNACE, overrides={key: value})
    assert str(raised.value) == tool_error(vpm_binary, FURNACE, "--set", "%s=%s" % (key, vpm._toml_value(value, key)))


def test_valid_overrides_reach_the_resolved_config():
    config = vpm.load_config(FURNACE, overrides={"photons.k": 16, "photons.estimator": "classic", "media.0.g": 0.0})
    photons = config.resolved["photons"]
    assert photons["k"] == 16 and photons["estimator"] == "classic"
    assert config.resolved["media"][0]["g"] == 0.0
    assert (config.width, config.height, config.integrator) == (64, 64, "photon_map")


def test_text_and_dict_configs_resolve_like_the_file():
    from_file = vpm.load_config(FURNACE)
    from_text = vpm.load_config(open(FURNACE).read())
    from_dict = vpm.load_config(from_file.resolved)
    assert from_text.resolved == from_file.resolved
    assert from_dict.resolved == from_file.resolved


def test_missing_file_raises_file_error_with_the_tools_message(vpm_binary, tmp_path):
    missing = str(tmp_path / "nope.toml")
    with pytest.raises(vpm.FileError) as raised:
        vpm.load_config(missing)
    assert str(raised.value) == tool_error(vpm_binary, missing)
    assert "nope.toml" in str(raised.value)


def test_bad_text_names_the_line():
    with pytest.raises(vpm.ConfigError, match=r"<string>:2: .*render\.width"):
        vpm.load_config("[render]\nwidth = 0\n")


def test_a_value_python_cannot_write_as_toml_is_refused():
    with pytest.raises(vpm.Error, match="photons.k"):
        vpm.load_config(FURNACE, overrides={"photons.k": object()})


def test_an_empty_source_is_a_file_error():
    for source in ("", "   "):
        with pytest.raises(vpm.FileError, match="got an empty string"):
            vpm.load_config(source)


def test_a_non_finite_dict_value_gets_the_range_message():
    with pytest.raises(vpm.ConfigError) as raised:
        vpm.load_config({"render": {"exposure": float("nan")}})
    message = str(raised.value)
    assert message.startswith("<dict>: render.exposure") and "out of range" in message, message
    with pytest.raises(vpm.ConfigError, match=r"<dict>: render\.exposure"):
        vpm.load_config({"render": {"exposure": float("inf")}})


def test_a_dict_value_json_cannot_carry_names_its_key():
    with pytest.raises(vpm.ConfigError, match=r"<dict>: photons\.k: a object cannot be a config value"):
        vpm.load_config({"photons": {"k": object()}})
    with pytest.raises(vpm.ConfigError, match="key must be a str"):
        vpm.load_config({"photons": {3: 8}})
