#!/usr/bin/env python3
"""The face scenes path-traced by Mitsuba 3 (scalar_rgb): the cross-check of the project's own
face truth (`dermis reference --scene head`, `tools/reference/face/`; compared by
`tools/mitsuba/crosscheck.py`).

Reads the scene dermis exports (`dermis render --scene head --export DIR`: DIR/scene.json and
DIR/head.ply, the head in metres) and renders, per light, the head as a homogeneous medium
(σ_a, σ_s, g from scene.json, mm⁻¹ scaled to m⁻¹) inside a rough dielectric boundary (η from
scene.json), with two independent seeds, plus the boundary's reflection alone (the same
boundary over a black interior) so the subsurface part can be scored on its own, and the
head's coverage (alpha). Writes PFMs and DIR/cache.json (Mitsuba version, integrator, sample
counts, seeds, times, and the sha256 of scene.json and head.ply the images were made from).

    python3 -m venv tools/mitsuba/.venv && tools/mitsuba/.venv/bin/pip install 'mitsuba==3.9.*' numpy
    dermis render --scene head --export DIR
    nice -n 15 tools/mitsuba/.venv/bin/python tools/mitsuba/render.py DIR --alpha 0.1 --size 32 \
        --spp 256 --seeds 1 2 3 4 5 6

Options: --alpha A (the boundary's GGX roughness, default 0.35: skin's specular lobe; the
cross-check uses 0.1, where the boundary loses ≤ 3 % of the light crossing it, see
docs/results/mitsuba-roughness.md), --spp N per channel and seed (default 256, or $SPP),
--face-normals (the triangles' normals, as the dermis truth walks them; default: Mitsuba's
interpolated shading normals), --seeds S... (default 1 2), --lights a,b (default all; or $LIGHTS), --size N (an N×N image
over the same field of view: the cross-check's integrals need samples, not pixels).

Facts this relies on (measured here): the llvm_* variants abort with LLVM 15, so scalar_rgb;
the volume path tracer cannot connect a point light through a smooth dielectric, so the
boundary is `roughdielectric`; `volpathmis` weights the three channels' distance sampling by
multiple importance sampling, which keeps skin's red (albedo 0.96) from the heavy-tailed
weights that single-channel distance sampling gives it.
"""

import argparse
import hashlib
import json
import os
import struct
import sys
import time

import mitsuba as mi

mi.set_variant("scalar_rgb")
T = mi.ScalarTransform4f

# GGX roughness of the boundary (--alpha): by default skin's specular lobe (Weyrich et al.
# 2006 fit Torrance-Sparrow roughness 0.3–0.45 on faces); the engine's models have no boundary
# roughness of their own, so this only shapes where the boundary lets light in and out.
ALPHA = 0.35
SPP = int(os.environ.get("SPP", "256"))
SPP_SPECULAR = int(os.environ.get("SPP_SPECULAR", "64"))
SEEDS = (1, 2)
# --face-normals: the triangles' own normals for the boundary (the dermis truth's), else the
# interpolated vertex normals (Mitsuba's shading normals).
FACE_NORMALS = False


def sha256(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def fnv1a64(path):
    """FNV-1a, 64 bits, as hex (dermis checks it without a hashing dependency)."""
    h = 0xCBF29CE484222325
    with open(path, "rb") as f:
        for b in f.read():
            h = ((h ^ b) * 0x100000001B3) & 0xFFFFFFFFFFFFFFFF
    return "%016x" % h


def write_pfm(path, tensors, channels):
    """Writes an RGB PFM (rows bottom to top) whose channel k is channel `channels[k]` of the
    (h, w, C) tensor `tensors[k]` (one tensor for all three when `tensors` is one)."""
    if not isinstance(tensors, list):
        tensors = [tensors] * 3
    h, w, c = tensors[0].shape
    flats = [list(t.array) for t in tensors]
    with open(path, "wb") as f:
        f.write(b"PF\n%d %d\n-1.0\n" % (w, h))
        for y in reversed(range(h)):
            row = []
            for x in range(w):
                base = (y * w + x) * c
                row.extend(flats[k][base + channels[k]] for k in range(3))
            f.write(struct.pack("<%df" % len(row), *row))


def scene_dict(scene, light, interior):
    cam = scene["camera"]
    eye, target, up = cam["eye"], cam["target"], cam["up"]
    return {
        "type": "scene",
        "integrator": {"type": "volpath", "max_depth": -1, "rr_depth": 64},
        "sensor": {
            "type": "perspective",
            "fov": cam["fov_y_deg"],
            "fov_axis": "y",
            "near_clip": 0.01,
            "far_clip": 100.0,
            "to_world": T().look_at(origin=eye, target=target, up=up),
            "film": {
                "type": "hdrfilm",
                "width": cam["width"],
                "height": cam["height"],
                "pixel_format": "rgba",
                "rfilter": {"type": "box"},
            },
            "sampler": {"type": "independent"},
        },
        "light": {
            "type": "point",
            "position": light["position"],
            "intensity": {"type": "rgb", "value": [light["intensity"]] * 3},
        },
        "head": {
            "type": "ply",
            "filename": scene["mesh"],
            "face_normals": FACE_NORMALS,
            "bsdf": {
                "type": "roughdielectric",
                "distribution": "ggx",
                "alpha": ALPHA,
                "int_ior": scene["medium"]["eta"],
                "ext_ior": 1.0,
            },
            "interior": interior,
        },
    }


def medium(scene, c):
    """Channel `c`'s medium, grey: every channel samples distances with its own σ_t."""
    m = scene["medium"]
    sa, ss = m["sigma_a_per_mm"][c], m["sigma_s_per_mm"][c]
    return {
        "type": "homogeneous",
        "sigma_t": {"type": "rgb", "value": [1.0] * 3},
        "albedo": {"type": "rgb", "value": [ss / (sa + ss)] * 3},
        "scale": 1000.0 * (sa + ss),  # mm⁻¹ → m⁻¹ (the mesh is in metres)
        "phase": {"type": "hg", "g": m["g"]},
    }


def black():
    """An interior that absorbs whatever crosses the boundary: only its reflection is left."""
    return {
        "type": "homogeneous",
        "sigma_t": {"type": "rgb", "value": [1.0] * 3},
        "albedo": {"type": "rgb", "value": [0.0] * 3},
        "scale": 1.0e7,
    }


def restamp(out):
    """Adds the FNV hashes to a cache.json written before they were recorded, after checking
    that the scene files still have the sha256 it holds."""
    path = os.path.join(out, "cache.json")
    with open(path) as f:
        record = json.load(f)
    for key, name in (("scene", "scene.json"), ("mesh", "head.ply")):
        if sha256(os.path.join(out, name)) != record[key + "_sha256"]:
            sys.exit("%s changed since it was rendered" % name)
        record[key + "_fnv1a64"] = fnv1a64(os.path.join(out, name))
    with open(path, "w") as f:
        json.dump(record, f, indent=2, sort_keys=True)
        f.write("\n")


def main():
    global ALPHA, SPP, SEEDS, FACE_NORMALS
    if len(sys.argv) == 3 and sys.argv[1] == "--restamp":
        return restamp(sys.argv[2])
    parser = argparse.ArgumentParser(description="DIR/scene.json, DIR/head.ply from dermis")
    parser.add_argument("dir")
    parser.add_argument("--alpha", type=float, default=ALPHA)
    parser.add_argument("--spp", type=int, default=SPP)
    parser.add_argument("--seeds", type=int, nargs="+", default=list(SEEDS))
    parser.add_argument("--lights", default=os.environ.get("LIGHTS"))
    parser.add_argument("--size", type=int, help="image side instead of scene.json's (the same "
                        "field of view: an integrated cross-check needs few pixels, many samples)")
    parser.add_argument("--face-normals", action="store_true")
    args = parser.parse_args()
    FACE_NORMALS = args.face_normals
    if not (0.0 < args.alpha <= 1.0) or args.spp < 1 or not args.seeds:
        sys.exit("render.py: --alpha must be in (0, 1], --spp at least 1, a seed given")
    ALPHA, SPP, SEEDS = args.alpha, args.spp, tuple(args.seeds)
    out = args.dir
    scene_path = os.path.join(out, "scene.json")
    with open(scene_path) as f:
        scene = json.load(f)
    if args.size:
        scene["camera"]["width"] = scene["camera"]["height"] = args.size
    cwd = os.getcwd()
    os.chdir(out)
    only = args.lights
    record = {
        "mitsuba": mi.__version__,
        "variant": mi.variant(),
        "integrator": "volpath (max_depth -1, rr_depth 64), one grey medium per channel",
        "boundary": "roughdielectric ggx alpha %.2f%s" % (
            ALPHA, ", face normals" if FACE_NORMALS else ", vertex normals"),
        "spp": SPP,
        "size": scene["camera"]["width"],
        "spp_specular": SPP_SPECULAR,
        "seeds": list(SEEDS),
        "scene_sha256": sha256("scene.json"),
        "mesh_sha256": sha256(scene["mesh"]),
        "scene_fnv1a64": fnv1a64("scene.json"),
        "mesh_fnv1a64": fnv1a64(scene["mesh"]),
        "renders": {},
    }
    if os.path.exists("cache.json"):
        with open("cache.json") as f:
            old = json.load(f)
        if old.get("scene_sha256") == record["scene_sha256"] and old.get("spp") == SPP:
            record["renders"] = old.get("renders", {})
    for light in scene["lights"]:
        name = light["name"]
        if only and name not in only.split(","):
            continue
        entry = {}
        grey = [mi.load_dict(scene_dict(scene, light, medium(scene, c))) for c in range(3)]
        for seed in SEEDS:
            t0 = time.time()
            # Channel c of the image is channel c of the render with channel c's medium.
            imgs = [mi.render(grey[c], spp=SPP, seed=seed) for c in range(3)]
            entry["seed%d_s" % seed] = round(time.time() - t0, 1)
            write_pfm("%s-seed%d.pfm" % (name, seed), imgs, (0, 1, 2))
            if not os.path.exists("alpha.pfm"):
                write_pfm("alpha.pfm", imgs[:1] * 3, (3, 3, 3))
            print(name, "seed", seed, entry["seed%d_s" % seed], "s", flush=True)
        spec = mi.load_dict(scene_dict(scene, light, black()))
        t0 = time.time()
        img = mi.render(spec, spp=SPP_SPECULAR, seed=SEEDS[0])
        entry["specular_s"] = round(time.time() - t0, 1)
        write_pfm("%s-specular.pfm" % name, img, (0, 1, 2))
        record["renders"][name] = entry
        with open("cache.json", "w") as f:
            json.dump(record, f, indent=2, sort_keys=True)
            f.write("\n")
    os.chdir(cwd)


if __name__ == "__main__":
    main()
