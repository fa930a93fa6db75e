#!/usr/bin/env python3
"""Does render.time_limit hold? Renders shipped configs with their pins removed (render.spp,
render.passes, photons.count: --unset where the file or its base sets them) under render.time_limit = T with
each integrator / gather, and prints a Markdown table of wall seconds against the contract
T * 1.2 + 1 s (issue 60), with the CPU seconds of the run (a loaded machine stretches the wall
time of a first pass, which is never cut short). Usage:

    python3 scripts/time_limit_contract.py --vpm build/vpm --limit 2 --out /tmp/tl \
        --configs default cornell_smoke --modes path collision march point_beam auto
"""
import argparse
import json
import os
import resource
import subprocess
import sys
import time
import tomllib

MODES = {
    "path": ["--set", "render.integrator=path"],
    "collision": ["--set", "render.integrator=photon_map", "--set", "photons.gather=collision"],
    "march": ["--set", "render.integrator=photon_map", "--set", "photons.gather=march"],
    "point_beam": ["--set", "render.integrator=photon_map", "--set", "photons.gather=point_beam"],
    "auto": ["--set", "render.integrator=auto", "--set", "photons.gather=auto"],
}
PINS = [("render", "spp"), ("render", "passes"), ("photons", "count"), ("photons", "gather")]


def pinned(path):
    """The PINS the config at `path` sets, itself or through its `base` chain."""
    with open(path, "rb") as f:
        doc = tomllib.load(f)
    keys = set()
    if "base" in doc:
        keys |= pinned(os.path.join(os.path.dirname(path), doc["base"]))
    return keys | {(t, k) for t, k in PINS if k in doc.get(t, {})}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--vpm", default="build/vpm")
    ap.add_argument("--limit", type=float, default=2.0)
    ap.add_argument("--out", required=True)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--configs", nargs="+", required=True, help="names in configs/ without .toml")
    ap.add_argument("--modes", nargs="+", default=list(MODES), choices=list(MODES))
    ap.add_argument("--timeout", type=float, default=300.0)
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    bound = 1.2 * a.limit + 1.0
    print(f"| config | mode | wall s | CPU s | passes | ran | within {bound:g} s |")
    print("|---|---|---|---|---|---|---|")
    for name in a.configs:
        path = os.path.join("configs", name + ".toml")
        pins = pinned(path)
        for mode in a.modes:
            unset = []
            for table, key in PINS:
                if (table, key) in pins:
                    unset += ["--unset", f"{table}.{key}"]
            out = os.path.join(a.out, f"{name}_{mode}.exr")
            cmd = [a.vpm, "render", path, "-q", "--threads", str(a.threads), "-o", out,
                   "--set", f"render.time_limit={a.limit}"] + unset + MODES[mode]
            t0 = time.monotonic()
            r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
            try:
                rc = subprocess.run(cmd, timeout=a.timeout, capture_output=True, text=True).returncode
            except subprocess.TimeoutExpired:
                rc = "timeout"
            wall = time.monotonic() - t0
            r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
            cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
            passes = ran = "-"
            if rc == 0:
                with open(out[:-4] + ".json") as f:
                    rec = json.load(f)
                passes = rec["passes"]["count"]
                ran = rec.get("integrator_used", "") + ("/" + rec["gather_used"] if rec.get("gather_used") else "")
            ok = "yes" if rc == 0 and wall <= bound else ("no" if rc == 0 else f"exit {rc}")
            print(f"| {name} | {mode} | {wall:.2f} | {cpu:.2f} | {passes} | {ran} | {ok} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
