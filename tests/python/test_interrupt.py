"""Ctrl-C in Python stops a render cleanly: KeyboardInterrupt, the interpreter usable, no files."""
import os
import signal
import subprocess
import sys
import textwrap

from conftest import FURNACE

# A render of 1.3e9 samples on one thread (tens of minutes): only a prompt stop (at the next image
# row, 1.3e6 samples) ends it within the test's time limit.
SCRIPT = textwrap.dedent("""
    import sys, vpm
    config = vpm.load_config(sys.argv[1], overrides={"render.width": 64, "render.height": 1024,
                                                     "render.spp": 20000, "photons.count": 20000})
    print("rendering", flush=True)
    try:
        vpm.render(config, threads=1, progress=False).save(sys.argv[2])
    except KeyboardInterrupt:
        # The interpreter goes on: a second, small render works.
        small = vpm.load_config(sys.argv[1], overrides={"render.width": 4, "render.height": 4, "photons.count": 1000})
        print("interrupted; then", vpm.render(small, progress=False).image.shape, flush=True)
""")


def test_ctrl_c_stops_a_render_and_writes_nothing(tmp_path):
    out = tmp_path / "never.exr"
    p = subprocess.Popen([sys.executable, "-c", SCRIPT, FURNACE, str(out)], stdout=subprocess.PIPE, text=True,
                         env=dict(os.environ))
    assert p.stdout.readline().strip() == "rendering"
    # Inside the camera pass (the 20000-photon pass takes well under a second).
    try:
        p.wait(timeout=2)
    except subprocess.TimeoutExpired:
        pass
    p.send_signal(signal.SIGINT)
    stdout, _ = p.communicate(timeout=120)
    assert p.returncode == 0
    assert "interrupted; then (4, 4, 3)" in stdout
    assert not any(tmp_path.iterdir())
