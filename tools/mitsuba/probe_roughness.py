#!/usr/bin/env python3
"""What the rough boundary of the Mitsuba references costs (issue 19).

tools/mitsuba/render.py gives the face a `roughdielectric` boundary (GGX alpha ALPHA) because
Mitsuba's volume path tracer cannot connect a point light through a smooth dielectric. This
script renders the reference's `point_light` probe (tools/reference/skin1.json: a flat
semi-infinite medium, η = 1.4, g = 0, σ_a / σ'_s per channel, an isotropic unit-power point
light at height h mm) in Mitsuba 3 with that rough boundary at several alphas, bins the image
into the reference's annuli and compares it with the project's Monte Carlo (smooth boundary).

Scene, in mm: a box 2W × 2W wide and D deep whose top face is z = 0 (roughdielectric, GGX,
int_ior η, ext_ior 1) holding a homogeneous grey medium (channel c's σ_t = σ_a + σ_s, σ_s = σ'_s
since g = 0, and its albedo in all three RGB slots, as render.py does); a point light of
intensity 1/(4π) W/sr (unit power) at (0, 0, h); an orthographic camera looking straight down
(-z) at the top face, pixel size `--pixel` mm. Integrator `volpath`, max_depth -1,
rr_depth 64 (as render.py). Each (h, alpha, channel, seed) is rendered twice: with the medium
(the full image) and over a black interior (the boundary's reflection alone, as render.py's
`black()`), and the subsurface part is the difference, because the reference excludes the
Fresnel reflection.

Quantity compared: the reference tabulates the diffuse exitance M(r) (mm⁻² per unit source
power, i.e. flux leaving per unit area, all directions). The camera measures the radiance
leaving toward +z, L(r). We compare π·L(r) (the exitance of a Lambertian emitter with that
normal radiance: what a renderer that shades with M/π would show) with M(r). For a smooth
boundary over an isotropic internal radiance, π·L_normal/M = KAPPA_SMOOTH (computed below,
≈ 1.053 at η = 1.4): recorded so the reader can separate that angular factor from the rest.

    python3 -m venv /tmp/mitsuba-venv && /tmp/mitsuba-venv/bin/pip install 'mitsuba==3.9.*'
    nice -n 15 /tmp/mitsuba-venv/bin/python tools/mitsuba/probe_roughness.py \
        --heights 2 5 --alphas 0.35 0.1 0.5 0.2 --seeds 1 2 --spp 48 --spp-specular 16 --threads 2
    nice -n 15 /tmp/mitsuba-venv/bin/python tools/mitsuba/probe_roughness.py \
        --heights 2 5 --alphas 0.1 0.05 --seeds 1 2 3 4 --spp 48 --spp-specular 16 --threads 2
    nice -n 15 /tmp/mitsuba-venv/bin/python tools/mitsuba/probe_roughness.py --summarise-only \
        --md /tmp/table.md

(/tmp/mitsuba-venv because tools/mitsuba/.venv is not git-ignored in this repository.)

Raw radial profiles are cached per render in --cache (resumable); the summary goes to
docs/results/mitsuba-roughness.json and .md.
"""

import argparse
import json
import math
import os
import time

import drjit as dr
import mitsuba as mi

mi.set_variant("scalar_rgb")
T = mi.ScalarTransform4f

W = 60.0  # half width of the medium box, mm (profile range ≤ 20 mm)
D = 60.0  # depth, mm (diffusion lengths ≤ 3.7 mm)


def fresnel(cos_i, eta):
    """Unpolarised Fresnel reflectance, light going from index 1 into index eta (cos_i ≥ 0)
    or, with eta < 1, from inside; 1 beyond the critical angle."""
    sin_t2 = (1.0 - cos_i * cos_i) / (eta * eta)
    if sin_t2 >= 1.0:
        return 1.0
    cos_t = math.sqrt(1.0 - sin_t2)
    rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t)
    rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t)
    return 0.5 * (rs * rs + rp * rp)


def kappa_smooth(eta, n=20000):
    """π L_out(normal) / M for a smooth boundary over isotropic internal radiance L_in:
    L_out(0) = (1 − F(0)) L_in / η², M = L_in ∫ (1 − F_inside(μ)) μ dω over the inside
    hemisphere (F_inside → 1 past the critical angle)."""
    num = (1.0 - fresnel(1.0, eta)) / (eta * eta)
    s = 0.0
    for i in range(n):
        mu = (i + 0.5) / n
        s += (1.0 - fresnel(mu, 1.0 / eta)) * mu / n
    return num / (2.0 * s)


def bsdf_albedo(alpha, eta, n=20000, seed=7):
    """Flux albedo (reflected + transmitted; TransportMode.Importance, so without the 1/η²
    radiance scaling of refraction) of Mitsuba's roughdielectric, i.e. the fraction of the
    flux that one boundary interaction keeps (1 for a smooth dielectric): at normal incidence
    from outside, and from inside averaged over a cosine-weighted (diffuse) hemisphere."""
    import random
    b = mi.load_dict({"type": "roughdielectric", "distribution": "ggx", "alpha": alpha,
                      "int_ior": eta, "ext_ior": 1.0})
    ctx = mi.BSDFContext(mi.TransportMode.Importance)
    rng = random.Random(seed)
    out = {}
    for name in ("outside_normal", "inside_diffuse"):
        tot = 0.0
        for _ in range(n):
            si = mi.SurfaceInteraction3f()
            si.n = mi.ScalarVector3f(0, 0, 1)
            si.sh_frame = mi.Frame3f(mi.ScalarVector3f(0, 0, 1))
            if name == "outside_normal":
                si.wi = mi.ScalarVector3f(0, 0, 1)
            else:
                u1, u2 = rng.random(), rng.random()
                r, ph = math.sqrt(u1), 2 * math.pi * u2
                si.wi = mi.ScalarVector3f(r * math.cos(ph), r * math.sin(ph),
                                          -math.sqrt(1 - u1))
            _, w = b.sample(ctx, si, rng.random(), mi.ScalarPoint2f(rng.random(), rng.random()))
            tot += w[0]
        out[name] = tot / n
    return out


def scene_dict(h, alpha, interior, half, npx, eta):
    return {
        "type": "scene",
        "integrator": {"type": "volpath", "max_depth": -1, "rr_depth": 64},
        "sensor": {
            "type": "orthographic",
            "near_clip": 1.0,
            "far_clip": 1000.0,
            "to_world": T().look_at(origin=[0, 0, 100.0], target=[0, 0, 0], up=[0, 1, 0])
            @ T().scale([half, half, 1.0]),
            "film": {
                "type": "hdrfilm",
                "width": npx,
                "height": npx,
                "pixel_format": "rgb",
                "rfilter": {"type": "box"},
            },
            "sampler": {"type": "independent"},
        },
        "light": {
            "type": "point",
            "position": [0.0, 0.0, h],
            "intensity": {"type": "rgb", "value": [1.0 / (4.0 * math.pi)] * 3},
        },
        "slab": {
            "type": "cube",
            "to_world": T().translate([0, 0, -D]) @ T().scale([W, W, D]),
            "bsdf": {
                "type": "roughdielectric",
                "distribution": "ggx",
                "alpha": alpha,
                "int_ior": eta,
                "ext_ior": 1.0,
            },
            "interior": interior,
        },
    }


def medium(ref, c):
    sa, ss = ref["sigma_a"][c], ref["sigma_s_prime"][c]  # g = 0: σ_s = σ'_s
    assert ref["g"] == 0.0
    return {
        "type": "homogeneous",
        "sigma_t": {"type": "rgb", "value": [1.0] * 3},
        "albedo": {"type": "rgb", "value": [ss / (sa + ss)] * 3},
        "scale": sa + ss,  # mm⁻¹, the scene is in mm
        "phase": {"type": "isotropic"},
    }


def black():
    return {
        "type": "homogeneous",
        "sigma_t": {"type": "rgb", "value": [1.0] * 3},
        "albedo": {"type": "rgb", "value": [0.0] * 3},
        "scale": 1.0e6,
    }


def radial(img, half, npx, edges):
    """Annulus means of the image's channel mean by pixel centre, and each annulus's standard
    error from the spread of its pixels (an overestimate: includes the radial gradient)."""
    arr = img.array if hasattr(img, "array") else img
    vals = list(arr)
    px = 2.0 * half / npx
    nb = len(edges) - 1
    s = [0.0] * nb
    s2 = [0.0] * nb
    n = [0] * nb
    bad = [0] * nb
    for y in range(npx):
        cy = -half + (y + 0.5) * px
        for x in range(npx):
            cx = -half + (x + 0.5) * px
            r = math.hypot(cx, cy)
            if r >= edges[-1]:
                continue
            # bins are few: linear search
            b = 0
            while r >= edges[b + 1]:
                b += 1
            base = (y * npx + x) * 3
            v = (vals[base] + vals[base + 1] + vals[base + 2]) / 3.0
            if not math.isfinite(v):
                # Mitsuba logs "Invalid sample value" for the odd NaN path and keeps the NaN
                # in its pixel: that pixel is left out of its annulus
                bad[b] += 1
                continue
            s[b] += v
            s2[b] += v * v
            n[b] += 1
    mean = [s[i] / n[i] if n[i] else float("nan") for i in range(nb)]
    se = []
    for i in range(nb):
        if n[i] > 1:
            var = max(s2[i] / n[i] - mean[i] ** 2, 0.0) * n[i] / (n[i] - 1)
            se.append(math.sqrt(var / n[i]))
        else:
            se.append(float("nan"))
    return mean, se, n, bad


def render_profile(ref, entry, alpha, c, seed, spp, spp_spec, pixel):
    h = entry["scene"]["h_mm"]
    edges = entry["edges"]
    half = edges[-1]
    npx = int(math.ceil(2.0 * half / pixel))
    half = npx * pixel / 2.0
    eta = ref["eta"]
    t0 = time.time()
    full = mi.render(mi.load_dict(scene_dict(h, alpha, medium(ref, c), half, npx, eta)),
                     spp=spp, seed=seed)
    t1 = time.time()
    spec = mi.render(mi.load_dict(scene_dict(h, alpha, black(), half, npx, eta)),
                     spp=spp_spec, seed=seed + 1000)
    t2 = time.time()
    lf, sef, n, bad = radial(full, half, npx, edges)
    ls, ses, _, bad_s = radial(spec, half, npx, edges)
    return {
        "h_mm": h, "alpha": alpha, "channel": c, "seed": seed, "spp": spp,
        "spp_specular": spp_spec, "pixel_mm": pixel, "npx": npx,
        "L_full": lf, "L_full_se": sef, "L_specular": ls, "L_specular_se": ses,
        "pixels_per_bin": n, "nan_pixels": sum(bad), "nan_pixels_specular": sum(bad_s),
        "wall_full_s": round(t1 - t0, 1), "wall_specular_s": round(t2 - t1, 1),
    }


def key(h, a, c, s):
    return "h%g_a%g_c%d_s%d" % (h, a, c, s)


def metrics(m, ref_v, ref_se, areas, mask=None):
    """mean |ln(m/ref)| over bins where ref > 3 SE, ref > 0 and m > 0; ∫m/∫ref over all."""
    bins = [i for i in range(len(ref_v))
            if ref_v[i] > 0 and ref_v[i] > 3 * ref_se[i] and m[i] > 0
            and (mask is None or mask[i])]
    lns = [math.log(m[i] / ref_v[i]) for i in bins]
    integ = sum(a * v for a, v in zip(areas, m)) / sum(a * v for a, v in zip(areas, ref_v))
    mean_abs = sum(abs(x) for x in lns) / len(lns) if lns else float("nan")
    # shape only: the log ratio with the integrated ratio divided out
    shape = (sum(abs(x - math.log(integ)) for x in lns) / len(lns)) if lns and integ > 0 \
        else float("nan")
    return {"mean_abs_ln": mean_abs, "integrated_ratio": integ, "shape_mean_abs_ln": shape,
            "bins_scored": len(bins), "ln_ratio_per_bin": [None if m[i] <= 0 or ref_v[i] <= 0
                                                           else math.log(m[i] / ref_v[i])
                                                           for i in range(len(ref_v))]}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--reference", default="tools/reference/skin1.json")
    ap.add_argument("--heights", type=float, nargs="+", default=[2.0, 5.0])
    ap.add_argument("--alphas", type=float, nargs="+", default=[0.1, 0.2, 0.35, 0.5])
    ap.add_argument("--channels", type=int, nargs="+", default=[0, 1, 2])
    ap.add_argument("--seeds", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--spp-specular", type=int, default=16)
    ap.add_argument("--pixel", type=float, nargs="+", default=None,
                    help="pixel size (mm) per height; default: a quarter of the first bin "
                         "width, at most 0.25 mm")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--cache", default="/tmp/mitsuba-roughness-cache.json")
    ap.add_argument("--out", default="docs/results/mitsuba-roughness.json")
    ap.add_argument("--deadline", type=float, default=None,
                    help="unix time after which no new render is started")
    ap.add_argument("--summarise-only", action="store_true")
    ap.add_argument("--md", default=None, help="also write the summary table (markdown) here")
    args = ap.parse_args()

    dr.set_thread_count(args.threads)
    with open(args.reference) as f:
        ref = json.load(f)
    entries = {e["scene"]["h_mm"]: e for e in ref["entries"]
               if e["scene"]["kind"] == "point_light"}
    cache = {}
    if os.path.exists(args.cache):
        with open(args.cache) as f:
            cache = json.load(f)

    if not args.summarise_only:
        # alphas outermost, so that a --deadline cuts whole alphas, not a height
        for a in args.alphas:
            for hi, h in enumerate(args.heights):
                e = entries[h]
                if args.pixel:
                    pixel = args.pixel[min(hi, len(args.pixel) - 1)]
                else:
                    pixel = min(0.25, (e["edges"][1] - e["edges"][0]) / 4.0)
                for c in args.channels:
                    for s in args.seeds:
                        k = key(h, a, c, s)
                        if k in cache and cache[k]["spp"] == args.spp:
                            continue
                        if args.deadline and time.time() > args.deadline:
                            print("deadline: skipping", k, flush=True)
                            continue
                        rec = render_profile(ref, e, a, c, s, args.spp, args.spp_specular,
                                             pixel)
                        cache[k] = rec
                        with open(args.cache, "w") as f:
                            json.dump(cache, f)
                        print(k, "full", rec["wall_full_s"], "s, specular",
                              rec["wall_specular_s"], "s", flush=True)

    summarise(ref, entries, cache, args)


def summarise(ref, entries, cache, args):
    kappa = kappa_smooth(ref["eta"])
    rows = []
    for h in sorted(entries):
        e = entries[h]
        edges = e["edges"]
        areas = [math.pi * (b * b - a * a) for a, b in zip(edges, edges[1:])]
        alphas = sorted({v["alpha"] for v in cache.values() if v["h_mm"] == h})
        for a in alphas:
            for c in range(3):
                recs = [v for v in cache.values()
                        if v["h_mm"] == h and v["alpha"] == a and v["channel"] == c]
                if not recs:
                    continue
                recs.sort(key=lambda v: v["seed"])
                ref_v = [v[c] for v in e["values"]]
                ref_se = [v[c] for v in e["std_err"]]
                # π L of the subsurface part, per seed, and the mean over seeds
                per_seed = [[math.pi * (f - s) for f, s in zip(r["L_full"], r["L_specular"])]
                            for r in recs]
                nb = len(ref_v)
                mean = [sum(p[i] for p in per_seed) / len(per_seed) for i in range(nb)]
                # Mitsuba SE of the seed mean, per bin, from the pixel spread (full and
                # specular renders independent)
                se = []
                for i in range(nb):
                    v = sum((r["L_full_se"][i] ** 2 + r["L_specular_se"][i] ** 2)
                            for r in recs) / len(recs) ** 2
                    se.append(math.pi * math.sqrt(v))
                mask = [mean[i] > 3 * se[i] for i in range(nb)]
                m = metrics(mean, ref_v, ref_se, areas, mask)
                row = {
                    "h_mm": h, "alpha": a, "channel": "RGB"[c], "seeds": [r["seed"] for r in recs],
                    "spp": recs[0]["spp"], "spp_specular": recs[0]["spp_specular"],
                    "pixel_mm": recs[0]["pixel_mm"], "npx": recs[0]["npx"],
                    "wall_s": sum(r["wall_full_s"] + r["wall_specular_s"] for r in recs),
                    "mean_abs_ln": m["mean_abs_ln"],
                    "integrated_ratio": m["integrated_ratio"],
                    "shape_mean_abs_ln": m["shape_mean_abs_ln"],
                    "integrated_ratio_over_kappa_smooth": m["integrated_ratio"] / kappa,
                    "bins_scored": m["bins_scored"],
                    "ln_ratio_per_bin": m["ln_ratio_per_bin"],
                    "pi_L_subsurface": mean,
                    "pi_L_subsurface_se": se,
                    "pi_L_specular_fraction_first_bin": (recs[0]["L_specular"][0]
                                                         / recs[0]["L_full"][0]
                                                         if recs[0]["L_full"][0] > 0 else None),
                    "mc_mean_rel_se": sum(ref_se[i] / ref_v[i] for i in range(nb)
                                          if ref_v[i] > 0) / nb,
                    "mitsuba_mean_rel_se": sum(se[i] / mean[i] for i in range(nb)
                                               if mean[i] > 0) / nb,
                }
                if len(per_seed) >= 2:
                    a0, a1 = per_seed[0], per_seed[1]
                    bins = [i for i in range(nb) if a0[i] > 0 and a1[i] > 0 and mask[i]]
                    row["seed_diff_mean_abs_ln"] = (sum(abs(math.log(a0[i] / a1[i]))
                                                        for i in bins) / len(bins)
                                                    if bins else None)
                    i0 = sum(w * v for w, v in zip(areas, a0))
                    i1 = sum(w * v for w, v in zip(areas, a1))
                    row["seed_diff_integrated_ln"] = abs(math.log(i0 / i1))
                rows.append(row)
    albedo = {"%g" % a: bsdf_albedo(a, ref["eta"])
              for a in sorted({v["alpha"] for v in cache.values()})}
    out = {
        "bsdf_albedo": albedo,
        "bsdf_albedo_note": "flux kept per boundary interaction by roughdielectric (20000 "
                            "samples each; smooth = 1): normal incidence from outside, "
                            "diffuse incidence from inside",
        "question": "issue 19: what the roughdielectric boundary of tools/mitsuba/render.py "
                    "changes on the point-light probe vs the project's Monte Carlo (smooth)",
        "reference": args.reference,
        "material": {k: ref[k] for k in ("material", "eta", "g", "sigma_a", "sigma_s_prime")},
        "mitsuba": mi.__version__,
        "variant": mi.variant(),
        "integrator": "volpath (max_depth -1, rr_depth 64), grey medium per channel",
        "scene": "box %g x %g mm wide, %g mm deep, top face z = 0, roughdielectric GGX "
                 "(int_ior eta, ext_ior 1) around a homogeneous medium (sigma_t = sigma_a + "
                 "sigma_s', isotropic phase); point light intensity 1/(4 pi) W/sr at (0,0,h); "
                 "orthographic camera looking down -z; box pixel filter" % (2 * W, 2 * W, D),
        "quantity": "pi * L_up(r): pi times the annulus-mean radiance leaving toward +z, minus "
                    "the same render over a black interior (boundary reflection only), "
                    "compared with the reference's diffuse exitance M(r) (mm^-2 per unit "
                    "source power)",
        "kappa_smooth": kappa,
        "kappa_smooth_note": "pi L_normal / M for a smooth boundary over isotropic internal "
                             "radiance (the Fresnel-weighted exit is not Lambertian); "
                             "integrated_ratio_over_kappa_smooth divides it out",
        "metric": "mean |ln(mitsuba/MC)| over bins where MC > 3 SE and > 0 and Mitsuba > 3 "
                  "of its own SE; integrated ratio = sum(area*mitsuba)/sum(area*MC) over all "
                  "bins; shape = mean |ln ratio - ln integrated ratio|; seed_diff_* = the same "
                  "between the two seeds (the seed mean's noise is about half of it)",
        "rows": rows,
    }
    with open(args.out, "w") as f:
        json.dump(out, f, indent=1)
        f.write("\n")
    if args.md:
        write_md(out, args.md)
    for r in rows:
        print("h=%g a=%.2f %s  mean|ln| %.3f  int %.3f  shape %.3f  seeddiff %s / %s  "
              "MC relSE %.3f  mits relSE %.3f  wall %.0f s" % (
                  r["h_mm"], r["alpha"], r["channel"], r["mean_abs_ln"],
                  r["integrated_ratio"], r["shape_mean_abs_ln"],
                  "%.3f" % r["seed_diff_mean_abs_ln"] if r.get("seed_diff_mean_abs_ln") is not None else "-",
                  "%.3f" % r["seed_diff_integrated_ln"] if "seed_diff_integrated_ln" in r else "-",
                  r["mc_mean_rel_se"], r["mitsuba_mean_rel_se"], r["wall_s"]))


def write_md(out, path):
    def f(x, fmt="%.3f"):
        return "–" if x is None or (isinstance(x, float) and math.isnan(x)) else fmt % x
    lines = [
        "| h (mm) | GGX α | ch | seeds × spp | mean \\|ln(M/MC)\\| | ∫M/∫MC | shape \\|ln\\| "
        "| seed-diff mean \\|ln\\| | seed-diff \\|ln ∫\\| | Mitsuba mean rel SE | MC mean rel SE |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in out["rows"]:
        lines.append("| %g | %g | %s | %d × %d | %s | %s | %s | %s | %s | %s | %s |" % (
            r["h_mm"], r["alpha"], r["channel"], len(r["seeds"]), r["spp"],
            f(r["mean_abs_ln"]), f(r["integrated_ratio"]), f(r["shape_mean_abs_ln"]),
            f(r.get("seed_diff_mean_abs_ln")), f(r.get("seed_diff_integrated_ln")),
            f(r["mitsuba_mean_rel_se"]), f(r["mc_mean_rel_se"])))
    lines += ["", "| GGX α | flux kept, normal incidence from outside | flux kept, diffuse "
              "incidence from inside |", "|---|---|---|"]
    for a, v in sorted(out["bsdf_albedo"].items(), key=lambda kv: float(kv[0])):
        lines.append("| %s | %.4f | %.4f |" % (a, v["outside_normal"], v["inside_diffuse"]))
    with open(path, "w") as fh:
        fh.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
