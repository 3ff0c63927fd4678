#!/usr/bin/env python3
"""The face truth against Mitsuba 3: integrated radiance per light and channel.

Compares the project's Monte Carlo truth (`dermis reference --scene head`, a cache such as
tools/reference/face: <light>.pfm, <light>-se.pfm, alpha.pfm) with Mitsuba's renders of the
same scene (`tools/mitsuba/render.py DIR --alpha A --seeds ...`: <light>-seed<k>.pfm and the
boundary's reflection <light>-specular.pfm), over the pixels the head covers wholly (alpha
from the truth). Mitsuba's image may be coarser by a whole factor k (`--size`): a coarse pixel
is the mean of the truth's k×k block, compared where the block is wholly on the head. Mitsuba's subsurface light is its render less the reflection; its noise is the
spread of the seeds; the truth's is the root sum of its per-pixel variances.

    tools/mitsuba/.venv/bin/python tools/mitsuba/crosscheck.py tools/reference/face DIR OUT
        (writes OUT.md and OUT.json)
"""

import json
import math
import os
import struct
import sys


def read_pfm(path):
    """(width, height, rows top to bottom of [r, g, b])."""
    with open(path, "rb") as f:
        data = f.read()
    head, dims, scale, body = data.split(b"\n", 3)
    if head != b"PF":
        sys.exit("%s: not an RGB PFM" % path)
    w, h = map(int, dims.split())
    little = float(scale) < 0
    vals = struct.unpack(("<" if little else ">") + "%df" % (w * h * 3), body[: w * h * 12])
    rows = [[vals[(y * w + x) * 3:(y * w + x) * 3 + 3] for x in range(w)] for y in range(h)]
    return w, h, rows[::-1]


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    truth_dir, mitsuba_dir, out = sys.argv[1:]
    with open(os.path.join(truth_dir, "truth.json")) as f:
        truth = json.load(f)
    with open(os.path.join(mitsuba_dir, "cache.json")) as f:
        record = json.load(f)
    tw, _, alpha = read_pfm(os.path.join(truth_dir, "alpha.pfm"))
    mw = record.get("size", tw)
    k = tw // mw
    if k * mw != tw:
        sys.exit("Mitsuba's %d pixels do not divide the truth's %d" % (mw, tw))
    # Coarse pixels wholly on the head, and each one's truth pixels.
    covered = [(y, x) for y in range(mw) for x in range(mw)
               if all(alpha[y * k + j][x * k + i][0] >= 0.999 for j in range(k) for i in range(k))]
    fine = {(y, x): [(y * k + j, x * k + i) for j in range(k) for i in range(k)] for y, x in covered}
    rows = []
    for name in record["renders"]:
        if name not in truth["lights"]:
            continue
        _, _, t = read_pfm(os.path.join(truth_dir, name + ".pfm"))
        _, _, tse = read_pfm(os.path.join(truth_dir, name + "-se.pfm"))
        _, _, spec = read_pfm(os.path.join(mitsuba_dir, name + "-specular.pfm"))
        seeds = [read_pfm(os.path.join(mitsuba_dir, "%s-seed%d.pfm" % (name, s)))[2]
                 for s in record["seeds"]]
        for c, ch in enumerate("RGB"):
            tsum = sum(t[j][i][c] for p in covered for j, i in fine[p])
            tvar = sum(tse[j][i][c] ** 2 for p in covered for j, i in fine[p])
            # A coarse pixel's mean times its k² fine pixels: the fine pixels' sum.
            msums = [k * k * sum(img[y][x][c] - spec[y][x][c] for y, x in covered) for img in seeds]
            n = len(msums)
            mmean = sum(msums) / n
            mse = math.sqrt(sum((m - mmean) ** 2 for m in msums) / (n - 1) / n) if n > 1 else 0.0
            ssum = k * k * sum(spec[y][x][c] for y, x in covered)
            ratio = mmean / tsum
            rse = ratio * math.sqrt((mse / mmean) ** 2 + tvar / tsum ** 2)
            rows.append({
                "light": name, "channel": ch, "truth": tsum, "truth_rel_se": math.sqrt(tvar) / tsum,
                "mitsuba": mmean, "mitsuba_rel_se": mse / mmean, "specular_share": ssum / (mmean + ssum),
                "ratio": ratio, "ratio_se": rse,
            })
    report = {
        "mitsuba": record["mitsuba"], "variant": record["variant"], "boundary": record["boundary"],
        "spp_per_channel_and_seed": record["spp"], "seeds": record["seeds"],
        "size": mw, "render_seconds": record["renders"], "covered_pixels": len(covered) * k * k,
        "rows": rows,
    }
    with open(out + ".json", "w") as f:
        json.dump(report, f, indent=2)
        f.write("\n")
    md = ["| light | channel | truth Σ L (rel. SE) | Mitsuba Σ L (rel. SE) | Mitsuba / truth | its SE |",
          "|---|---|---|---|---|---|"]
    for r in rows:
        md.append("| %s | %s | %.2f (%.4f) | %.2f (%.4f) | %.3f | %.3f |" % (
            r["light"], r["channel"], r["truth"], r["truth_rel_se"], r["mitsuba"],
            r["mitsuba_rel_se"], r["ratio"], r["ratio_se"]))
    with open(out + ".md", "w") as f:
        f.write("\n".join(md) + "\n")
    print("\n".join(md))


if __name__ == "__main__":
    main()
