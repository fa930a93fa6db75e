#!/usr/bin/env python3
"""Render a vpm scene file with Mitsuba 3's volumetric path tracer (volpath, scalar_rgb).

A benchmark tool, not a dependency of vpm: it needs the `mitsuba` wheel, which CI does not install.
Install it into a virtual environment outside the repository, e.g.

    /usr/bin/python3 -m venv /work/venv-mitsuba
    /work/venv-mitsuba/bin/pip install mitsuba numpy        # mitsuba 3.9.1 measured here

and run this script with that interpreter:

    /work/venv-mitsuba/bin/python bench/mitsuba/vpm_scene.py configs/glass_sphere_fog.toml \
        --spp 64 --seed 1 --threads 2 --size 64x64 -o out/mitsuba/sphere_64_1.exr

It prints one JSON line: the spp, the CPU seconds (user + system) of the render call alone (the
scene is built before it), the wall seconds and the image mean.

Only what the caustic scenes use is translated (anything else is an error naming the key):
- camera: position / look_at / up / fov (vpm's fov is vertical: fov_axis = "y"); a camera inside a
  medium box gets that medium;
- lights: "sphere" (a black sphere with an area emitter of the same radiance: vpm's sphere light
  emits outwards and absorbs what meets it) and "environment" with a constant radiance;
- media: "homogeneous" boxes and spheres, sigma_t = sigma_t_scale, albedo, Henyey-Greenstein g
  (the same sign convention: g > 0 scatters forwards);
- shapes: "quad" (center, u, v: half-extents), "box" (min, max), "sphere" and "mesh" (OBJ, flat
  normals; a dielectric mesh wound inwards is reversed, as vpm orients it; one closed part only:
  vpm's shells, a part inside another, are not handled), Lambertian
  (two-sided, as vpm's) or "dielectric" (ior inside, air outside).

Media in Mitsuba live inside shapes: a medium box or sphere becomes a shape with a null BSDF whose
interior is that medium, and every other shape inside it gets it as interior and exterior medium
(a glass sphere in fog has fog on both sides, as vpm fills glass with the medium its table puts
there). Faces of a medium box that coincide with a wall or a floor would make the two surfaces
fight; the box is grown by `--medium-pad` (default 2e-3) on faces with nothing beyond them and
shrunk on faces that lie on a dielectric's faces (the water's murky layer), so that each ray meets
them in the order vpm's geometry implies. The pad must exceed Mitsuba's ray-spawn offset (about
1e-4 x (1 + the largest coordinate) in single precision): with 1e-4, rays leaving the murky layer's
side skipped the water's side face 1e-4 beyond it and left the water unrefracted, which read the
water scene 23% dark. The pad changes optical depths by <= sigma_t x 2e-3.
"""
import argparse
import json
import math
import os
import resource
import sys
import time
import tomllib


def fail(msg):
    sys.exit(f"vpm_scene.py: {msg}")


def vec(v):
    return [float(x) for x in v]


def rgb(v):
    if isinstance(v, (int, float)):
        return [float(v)] * 3
    return vec(v)


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def norm(a):
    n = math.sqrt(sum(x * x for x in a))
    return [x / n for x in a]


def apply_set(cfg, key, value):
    """--set a.b=value (TOML value) like vpm's --set for the keys the bench needs."""
    parts = key.split(".")
    node = cfg
    for p in parts[:-1]:
        node = node[int(p)] if isinstance(node, list) else node.setdefault(p, {})
    last = parts[-1]
    parsed = tomllib.loads(f"x = {value}")["x"]
    if isinstance(node, list):
        node[int(last)] = parsed
    else:
        node[last] = parsed


def read_obj(path):
    verts, faces = [], []
    with open(path) as f:
        for line in f:
            t = line.split()
            if not t:
                continue
            if t[0] == "v":
                verts.append([float(x) for x in t[1:4]])
            elif t[0] == "f":
                idx = [int(x.split("/")[0]) for x in t[1:]]
                idx = [i - 1 if i > 0 else len(verts) + i for i in idx]
                faces.extend([idx[0], idx[k], idx[k + 1]] for k in range(1, len(idx) - 1))
    return verts, faces


def signed_volume(verts, faces):
    v = 0.0
    for a, b, c in faces:
        v += sum(x * y for x, y in zip(verts[a], cross(verts[b], verts[c]))) / 6.0
    return v


def write_reversed_obj(verts, faces, path):
    import tempfile
    fd, out = tempfile.mkstemp(suffix="_" + os.path.basename(path))
    with os.fdopen(fd, "w") as f:
        for v in verts:
            f.write(f"v {v[0]!r} {v[1]!r} {v[2]!r}\n")
        for a, b, c in faces:
            f.write(f"f {a + 1} {c + 1} {b + 1}\n")
    return out


class Box:
    def __init__(self, lo, hi):
        self.lo, self.hi = lo, hi

    def contains(self, p, eps=1e-9):
        return all(self.lo[i] - eps <= p[i] <= self.hi[i] + eps for i in range(3))


def build_scene(cfg, config_dir, width, height, spp, seed, max_depth, rr_depth, medium_pad):
    import mitsuba as mi
    T = mi.ScalarTransform4f

    scene = {"type": "scene"}
    scene["integrator"] = {"type": "volpath", "max_depth": max_depth, "rr_depth": rr_depth}

    # Media: each one a shape with a null BSDF holding it.
    media = []   # (name, kind, geometry)
    for i, m in enumerate(cfg.get("media", [])):
        if float(m.get("sigma_t_scale", 1.0)) == 0.0:
            continue   # an empty medium (e.g. --set media.0.sigma_t_scale=0 for a clear variant)
        if m.get("type") != "homogeneous":
            fail(f"media.{i}.type = {m.get('type')!r}: only \"homogeneous\" is translated")
        name = f"medium{i}"
        medium = {"type": "homogeneous", "sigma_t": float(m.get("sigma_t_scale", 1.0)),
                  "albedo": {"type": "rgb", "value": rgb(m.get("albedo", 1.0))},
                  "phase": {"type": "hg", "g": float(m.get("g", 0.0))}}
        scene[name] = medium
        shape = m.get("shape", "box")
        if shape == "box":
            media.append((name, "box", Box(vec(m["min"]), vec(m["max"]))))
        elif shape == "sphere":
            media.append((name, "sphere", (vec(m["center"]), float(m["radius"]))))
        else:
            fail(f"media.{i}.shape = {shape!r}: only \"box\" and \"sphere\" are translated")

    def medium_at(p):
        """The medium table whose region holds point p (vpm: the first one)."""
        for name, kind, geo in media:
            if kind == "box" and geo.contains(p):
                return name
            if kind == "sphere":
                c, r = geo
                if sum((p[k] - c[k]) ** 2 for k in range(3)) <= r * r * (1 + 1e-9):
                    return name
        return None

    def ref(name):
        return {"type": "ref", "id": name}

    def with_media(d, inside, outside):
        if inside:
            d["interior"] = ref(inside)
        if outside:
            d["exterior"] = ref(outside)
        return d

    # Dielectric mesh boxes (for the padding rule) are collected while translating shapes.
    dielectric_bounds = []
    shapes = cfg.get("shapes", [])
    for i, s in enumerate(shapes):
        kind = s.get("type")
        material = s.get("material", "lambertian")
        if material not in ("lambertian", "dielectric"):
            fail(f"shapes.{i}.material = {material!r}: only lambertian and dielectric are translated")
        if material == "dielectric":
            bsdf = {"type": "dielectric", "int_ior": float(s.get("ior", 1.5)), "ext_ior": 1.0}
            if "transmittance" in s:
                fail(f"shapes.{i}.transmittance: not translated")
        else:
            bsdf = {"type": "twosided", "bsdf": {"type": "diffuse",
                                                 "reflectance": {"type": "rgb", "value": rgb(s.get("reflectance", 0.5))}}}
        if kind == "quad":
            c, u, v = vec(s["center"]), vec(s["u"]), vec(s["v"])
            n = norm(cross(u, v))
            mat = [[u[0], v[0], n[0], c[0]], [u[1], v[1], n[1], c[1]], [u[2], v[2], n[2], c[2]], [0, 0, 0, 1]]
            d = {"type": "rectangle", "to_world": T(mat), "bsdf": bsdf}
            med = medium_at(c)
            d = with_media(d, med, med)
        elif kind == "sphere":
            c, r = vec(s["center"]), float(s["radius"])
            d = {"type": "sphere", "center": c, "radius": r, "bsdf": bsdf}
            if "interior_medium" in s:
                fail(f"shapes.{i}.interior_medium: not translated")
            # Inside: the medium at the centre, unless that medium is a sphere inside this one
            # (the flask's smoke: its own shape holds it); outside: the medium just beyond the surface.
            inside = medium_at(c)
            for name, mk, geo in media:
                if name == inside and mk == "sphere" and geo[1] < r:
                    inside = None
            outside = medium_at([c[0], c[1] + r * 1.0001, c[2]])
            d = with_media(d, inside, outside)
        elif kind == "box":
            lo, hi = vec(s["min"]), vec(s["max"])
            if "transform" in s:
                fail(f"shapes.{i}.transform: not translated")
            c = [(lo[k] + hi[k]) / 2 for k in range(3)]
            h = [(hi[k] - lo[k]) / 2 for k in range(3)]
            mat = [[h[0], 0, 0, c[0]], [0, h[1], 0, c[1]], [0, 0, h[2], c[2]], [0, 0, 0, 1]]
            d = {"type": "cube", "to_world": T(mat), "bsdf": bsdf}
            if material == "dielectric":
                dielectric_bounds.append(Box(lo, hi))
            d = with_media(d, None, medium_at([lo[0] - 1e-3, hi[1] + 1e-3, lo[2] - 1e-3]))
        elif kind == "mesh":
            path = os.path.join(config_dir, s["file"])
            if "transform" in s:
                fail(f"shapes.{i}.transform: not translated")
            verts, faces = read_obj(path)
            lo = [min(v[k] for v in verts) for k in range(3)]
            hi = [max(v[k] for v in verts) for k in range(3)]
            if material == "dielectric":
                dielectric_bounds.append(Box(lo, hi))
                # Mitsuba reads which side is glass from the winding; vpm turns each closed part to
                # face out of the glass itself. A mesh wound inwards is written out reversed.
                if signed_volume(verts, faces) < 0.0:
                    path = write_reversed_obj(verts, faces, path)
            d = {"type": "obj", "filename": path, "face_normals": True, "bsdf": bsdf}
            # A medium box inside the mesh is its own shape (below); the glass holds no medium of its own.
            outside = medium_at([lo[0] - 1e-3, hi[1] + 1e-3, lo[2] - 1e-3])
            d = with_media(d, None, outside)
        else:
            fail(f"shapes.{i}.type = {kind!r}: not translated")
        scene[f"shape{i}"] = d

    # Medium shapes.
    for name, kind, geo in media:
        if kind == "box":
            lo, hi = list(geo.lo), list(geo.hi)
            for k in range(3):
                for side, val in ((0, lo[k]), (1, hi[k])):
                    on_mesh = any(abs(val - (b.lo[k] if side == 0 else b.hi[k])) < 1e-6 for b in dielectric_bounds)
                    grow = -medium_pad if on_mesh else medium_pad
                    if side == 0:
                        lo[k] = val - grow
                    else:
                        hi[k] = val + grow
            c = [(lo[k] + hi[k]) / 2 for k in range(3)]
            h = [(hi[k] - lo[k]) / 2 for k in range(3)]
            mat = [[h[0], 0, 0, c[0]], [0, h[1], 0, c[1]], [0, 0, h[2], c[2]], [0, 0, 0, 1]]
            scene[name + "_shape"] = {"type": "cube", "to_world": T(mat), "bsdf": {"type": "null"},
                                      "interior": ref(name)}
        else:
            c, r = geo
            scene[name + "_shape"] = {"type": "sphere", "center": c, "radius": r, "bsdf": {"type": "null"},
                                      "interior": ref(name)}

    for i, l in enumerate(cfg.get("lights", [])):
        kind = l.get("type")
        if kind == "sphere":
            c, r = vec(l["center"]), float(l["radius"])
            d = {"type": "sphere", "center": c, "radius": r,
                 "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0.0, 0.0, 0.0]}},
                 "emitter": {"type": "area", "radiance": {"type": "rgb", "value": rgb(l["radiance"])}}}
            med = medium_at([c[0], c[1] + r * 1.0001, c[2]])
            scene[f"light{i}"] = with_media(d, None, med)
        elif kind == "environment":
            if "file" in l:
                fail(f"lights.{i}.file: only a constant environment is translated")
            scene[f"light{i}"] = {"type": "constant", "radiance": {"type": "rgb", "value": rgb(l["radiance"])}}
        else:
            fail(f"lights.{i}.type = {kind!r}: only sphere and environment lights are translated")

    cam = cfg.get("camera", {})
    pos, target = vec(cam.get("position", [0, 1, 4])), vec(cam.get("look_at", [0, 1, 0]))
    up = vec(cam.get("up", [0, 1, 0]))
    sensor = {"type": "perspective", "fov": float(cam.get("fov", 40.0)), "fov_axis": "y",
              "to_world": T().look_at(origin=pos, target=target, up=up),
              "film": {"type": "hdrfilm", "width": width, "height": height, "rfilter": {"type": "box"},
                       "pixel_format": "rgb", "component_format": "float32"},
              "sampler": {"type": "independent", "sample_count": spp, "seed": seed}}
    cam_medium = medium_at(pos)
    if cam_medium:
        sensor["medium"] = ref(cam_medium)
    scene["sensor"] = sensor
    return scene


def cpu_seconds():
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("config")
    ap.add_argument("-o", "--output", required=True)
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--size", default=None, help="WxH (default: the config's render.width x height)")
    ap.add_argument("--max-depth", type=int, default=-1)
    ap.add_argument("--rr-depth", type=int, default=5)
    ap.add_argument("--medium-pad", type=float, default=2e-3)
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    ap.add_argument("--unset", action="append", default=[], metavar="KEY")
    ap.add_argument("--variant", default="scalar_rgb")
    args = ap.parse_args()

    with open(args.config, "rb") as f:
        cfg = tomllib.load(f)
    for kv in args.set:
        k, v = kv.split("=", 1)
        apply_set(cfg, k, v)
    for key in args.unset:
        parts = key.split(".")
        node = cfg
        for p in parts[:-1]:
            node = node[int(p)] if isinstance(node, list) else node[p]
        node.pop(parts[-1], None)
    render = cfg.get("render", {})
    width, height = int(render.get("width", 256)), int(render.get("height", 256))
    if args.size:
        width, height = (int(x) for x in args.size.lower().split("x"))

    import drjit as dr
    import mitsuba as mi
    mi.set_variant(args.variant)
    dr.set_thread_count(args.threads)
    scene = mi.load_dict(build_scene(cfg, os.path.dirname(os.path.abspath(args.config)), width, height,
                                     args.spp, args.seed, args.max_depth, args.rr_depth, args.medium_pad))
    c0, w0 = cpu_seconds(), time.time()
    image = mi.render(scene, spp=args.spp, seed=args.seed)
    c1, w1 = cpu_seconds(), time.time()
    os.makedirs(os.path.dirname(os.path.abspath(args.output)), exist_ok=True)
    bmp = mi.Bitmap(image)
    bmp.write(args.output)
    import numpy as np
    arr = np.array(image)
    print(json.dumps({"config": args.config, "spp": args.spp, "seed": args.seed, "threads": args.threads,
                      "cpu_s": round(c1 - c0, 3), "wall_s": round(w1 - w0, 3),
                      "mean_rgb": [float(x) for x in arr.reshape(-1, 3).mean(axis=0)]}))


if __name__ == "__main__":
    main()
