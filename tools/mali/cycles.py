#!/usr/bin/env python3
"""Mali cycle counts for a directory of SPIR-V shaders (Python 3 stdlib only).

For every NAME.frag.spv / NAME.vert.spv (and NAME.comp.spv) in DIR, runs Mesa's
bifrost_compiler (built by tools/mali/build.sh) with `compile-spirv` for each
GPU (default G52 = Bifrost v7, G57 = Valhall v9), parses Mesa's shader-db
statistics line(s) and prints one JSON object on stdout and a table on stderr.

    python3 tools/mali/cycles.py [--compiler PATH] [--gpus G52,G57] DIR

The entry point is taken from the module's OpEntryPoint of the right stage
(vs_main / fs_main preferred when there are several).
"""

import argparse
import json
import os
import re
import struct
import subprocess
import sys

COMPILER_LABEL = "Mesa 22.3.6 bifrost_compiler (spirv)"
STAGES = {"vert": 0, "frag": 4, "comp": 5}  # SPIR-V ExecutionModel per stage
PREFERRED_ENTRY = {"vert": "vs_main", "frag": "fs_main", "comp": "cs_main"}
GPU_ARCH = {"G71": "Bifrost v6", "G72": "Bifrost v6", "G51": "Bifrost v7",
            "G76": "Bifrost v7", "G52": "Bifrost v7", "G31": "Bifrost v7",
            "G77": "Valhall v9", "G57": "Valhall v9", "G78": "Valhall v9",
            "G68": "Valhall v9", "G78AE": "Valhall v9"}
# Cycle columns of Mesa's shader-db line, per architecture (bi_print_stats /
# va_print_stats in src/panfrost/bifrost/bifrost_compile.c).
CYCLE_COLUMNS = {
    "bifrost": ["arith", "texture", "vary", "ldst"],
    "valhall": ["fma", "cvt", "sfu", "v", "t", "ls"],
}
VARIANT_NAMES = {"MESA_SHADER_POSITION": "position",
                 "MESA_SHADER_VARYING": "varying"}


def spirv_entry_points(path):
    """[(execution_model, name)] of a SPIR-V module."""
    with open(path, "rb") as f:
        data = f.read()
    if len(data) < 20 or len(data) % 4:
        raise ValueError("not a SPIR-V module")
    endian = "<" if struct.unpack("<I", data[:4])[0] == 0x07230203 else ">"
    words = struct.unpack(endian + "%dI" % (len(data) // 4), data)
    if words[0] != 0x07230203:
        raise ValueError("not a SPIR-V module (bad magic)")
    out, i = [], 5
    while i < len(words):
        count, opcode = words[i] >> 16, words[i] & 0xFFFF
        if count == 0:
            raise ValueError("malformed SPIR-V (zero-length instruction)")
        if opcode == 15:  # OpEntryPoint
            raw = struct.pack(endian + "%dI" % (count - 3), *words[i + 3:i + count])
            name = raw.split(b"\0", 1)[0].decode("utf-8", "replace")
            out.append((words[i + 1], name))
        i += count
    return out


def pick_entry(path, stage):
    eps = [name for model, name in spirv_entry_points(path) if model == STAGES[stage]]
    if not eps:
        raise ValueError("no %s entry point in module" % stage)
    return PREFERRED_ENTRY[stage] if PREFERRED_ENTRY[stage] in eps else eps[0]


def parse_number(text):
    return float(text) if "." in text else int(text)


def parse_shaderdb(line):
    """'MESA_SHADER_FRAGMENT shader: 12 inst, 0.5 cycles, ...' -> (stage, {key: value})."""
    stage, _, rest = line.partition(" shader: ")
    fields = {}
    for item in rest.split(", "):
        value, _, key = item.strip().partition(" ")
        if key == "spills:fills":
            spills, fills = value.split(":")
            fields["spills"], fields["fills"] = int(spills), int(fills)
        else:
            fields[key] = parse_number(value)
    return stage.strip(), fields


def stats_entry(fields, registers):
    arch = "valhall" if "fma" in fields else "bifrost"
    cols = {c: round(fields[c], 6) for c in CYCLE_COLUMNS[arch]}
    entry = {
        "instructions": fields["inst"],
        "cycles": cols,
        "bound": round(fields["cycles"], 6),
        "registers": registers,
        "threads": fields["threads"],
    }
    for key in ("tuples", "clauses", "quadwords", "preloads", "loops", "spills", "fills"):
        if key in fields:
            entry[key] = fields[key]
    if "preloads" in fields:  # Bifrost v7: cost of preloaded messages, in 1/16 cycle
        entry["preload_cycles"] = round(fields["preloads"] / 16.0, 6)
    return entry


def combine_variants(variants):
    """IDVS vertex shader: position + varying shader summed (a visible vertex runs both)."""
    first = next(iter(variants.values()))
    cols = {c: round(sum(v["cycles"][c] for v in variants.values()), 6) for c in first["cycles"]}
    out = {
        "instructions": sum(v["instructions"] for v in variants.values()),
        "cycles": cols,
        "bound": round(max(cols.values()), 6),
        "registers": max(v["registers"] for v in variants.values() if v["registers"] is not None),
        "threads": min(v["threads"] for v in variants.values()),
    }
    for key in ("tuples", "clauses", "quadwords", "loops", "spills", "fills"):
        if all(key in v for v in variants.values()):
            out[key] = sum(v[key] for v in variants.values())
    out["idvs"] = True
    out["variants"] = variants
    return out


INFO_RE = re.compile(r"SPIRV-INFO: \S+ shader: (\d+) work registers, (\d+) secondary work registers, (idvs|no idvs)")


def compile_one(compiler, gpu, path, stage, timeout, ubo_push=True, idvs=True):
    entry = pick_entry(path, stage)
    env = dict(os.environ, BIFROST_MESA_DEBUG="shaderdb" if idvs else "shaderdb,noidvs")
    env.pop("BIFROST_SPIRV_NO_UBO_PUSH", None)
    if not ubo_push:
        env["BIFROST_SPIRV_NO_UBO_PUSH"] = "1"
    cmd = [compiler, "--gpu=" + gpu, "compile-spirv", path, stage, entry]
    try:
        proc = subprocess.run(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                              timeout=timeout)
    except subprocess.TimeoutExpired:
        raise RuntimeError("compiler timed out after %d s" % timeout)
    text = proc.stderr.decode("utf-8", "replace") + proc.stdout.decode("utf-8", "replace")
    dbs = [l.split("SHADER-DB: ", 1)[1] for l in text.splitlines() if "SHADER-DB: " in l]
    info = INFO_RE.search(text)
    if proc.returncode != 0 or not dbs or not info:
        tail = " | ".join(l for l in text.strip().splitlines()[-6:] if l.strip())
        sig = (" (signal %d)" % -proc.returncode) if proc.returncode < 0 else ""
        raise RuntimeError("bifrost_compiler exit %d%s: %s" % (proc.returncode, sig, tail or "no output"))
    main_regs, secondary_regs, idvs = int(info.group(1)), int(info.group(2)), info.group(3) == "idvs"
    if len(dbs) == 1:
        _, fields = parse_shaderdb(dbs[0])
        entry_stats = stats_entry(fields, main_regs)
    else:
        variants = {}
        for line in dbs:
            name, fields = parse_shaderdb(line)
            key = VARIANT_NAMES.get(name, name)
            regs = secondary_regs if key == "varying" else main_regs
            variants[key] = stats_entry(fields, regs)
        entry_stats = combine_variants(variants)
    entry_stats["entry_point"] = entry
    return entry_stats


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dir", help="directory with NAME.frag.spv / NAME.vert.spv")
    ap.add_argument("--compiler", default=os.environ.get("MALI_COMPILER"),
                    help="bifrost_compiler path (default: $MALI_COMPILER, else the cache of build.sh)")
    ap.add_argument("--gpus", default="G52,G57", help="comma-separated Mali GPUs (default G52,G57)")
    ap.add_argument("--timeout", type=int, default=120, help="seconds per compile (default 120)")
    ap.add_argument("--no-ubo-push", action="store_true",
                    help="keep UBO loads as loads (panvk 22.3 behaviour) instead of promoting "
                         "them to uniform registers (gallium driver behaviour, the default)")
    ap.add_argument("--no-idvs", action="store_true",
                    help="compile vertex shaders as one shader instead of IDVS position + varying")
    args = ap.parse_args()

    compiler = args.compiler
    if not compiler:
        cache = os.environ.get("MALI_BUILD_DIR", os.path.expanduser("~/.cache/dermis-mali"))
        compiler = os.path.join(cache, "bin", "bifrost_compiler")
    if not os.access(compiler, os.X_OK):
        sys.exit("cycles.py: no compiler at %s; run %s/build.sh first" % (compiler, here))
    gpus = [g.strip() for g in args.gpus.split(",") if g.strip()]
    for g in gpus:
        if g not in GPU_ARCH:
            sys.exit("cycles.py: unknown GPU %s (known: %s)" % (g, ", ".join(GPU_ARCH)))

    shaders = {}
    pattern = re.compile(r"^(.+)\.(vert|frag|comp)\.spv$")
    for fn in sorted(os.listdir(args.dir)):
        m = pattern.match(fn)
        if m:
            shaders.setdefault(m.group(1), {})[m.group(2)] = os.path.join(args.dir, fn)
    if not shaders:
        sys.exit("cycles.py: no NAME.vert.spv / NAME.frag.spv in %s" % args.dir)

    mesa_version = None
    vfile = os.path.join(os.path.dirname(compiler), "MESA_VERSION")
    if os.path.exists(vfile):
        with open(vfile) as f:
            mesa_version = f.read().strip()

    result = {
        "compiler": COMPILER_LABEL,
        "mesa_debian_version": mesa_version,
        "gpus": {g: GPU_ARCH[g] for g in gpus},
        "cycle_columns": {"bifrost": CYCLE_COLUMNS["bifrost"], "valhall": CYCLE_COLUMNS["valhall"]},
        "options": {"ubo_push": not args.no_ubo_push, "idvs": not args.no_idvs},
        "shaders": {},
    }
    rows = []
    for name, stages in shaders.items():
        per_gpu = {}
        for gpu in gpus:
            per_stage = {}
            for stage in ("vert", "frag", "comp"):
                if stage not in stages:
                    continue
                try:
                    st = compile_one(compiler, gpu, stages[stage], stage, args.timeout,
                                     ubo_push=not args.no_ubo_push, idvs=not args.no_idvs)
                    per_stage[stage] = st
                    rows.append((name, gpu, stage, st))
                except Exception as e:  # one shader's failure must not stop the rest
                    per_stage[stage] = {"error": str(e)}
                    rows.append((name, gpu, stage, {"error": str(e)}))
            per_gpu[gpu] = per_stage
        result["shaders"][name] = per_gpu

    json.dump(result, sys.stdout, indent=2)
    sys.stdout.write("\n")

    # Human table on stderr
    err = sys.stderr
    err.write("\n%-20s %-4s %-5s %6s %9s  %-52s %4s %3s\n" %
              ("shader", "gpu", "stage", "inst", "bound", "cycles per unit", "regs", "thr"))
    for name, gpu, stage, st in rows:
        if "error" in st:
            err.write("%-20s %-4s %-5s ERROR %s\n" % (name, gpu, stage, st["error"][:200]))
            continue
        cols = " ".join("%s=%.3g" % (k, v) for k, v in st["cycles"].items())
        err.write("%-20s %-4s %-5s %6d %9.4f  %-52s %4s %3d\n" %
                  (name, gpu, stage + ("*" if st.get("idvs") else ""), st["instructions"],
                   st["bound"], cols, st["registers"], st["threads"]))
    if any(st.get("idvs") for *_, st in rows):
        err.write("* IDVS vertex shader: position + varying variants summed (see JSON 'variants')\n")


if __name__ == "__main__":
    main()
