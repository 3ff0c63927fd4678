#!/usr/bin/env python3
"""Generates tests/data/hostile/: corrupt, truncated and hostile .glb/.gltf files, plus
index.tsv (file <TAB> substring <TAB> outcome): an `error` file must fail with an error
containing the substring; a `warning` file (a bad material value, a texture missing or not
decoding) must load, with a warning containing it. game/tests/allocs/hostile.rs loads every
listed file and checks. Also the valid fixtures of tests/data (skinned.glb, embedded.gltf,
external/, materials/).

Usage: python3 tools/hostile-corpus/make.py   (from the repository root or anywhere)
Everything is deterministic; re-running rewrites the same bytes.
"""
import base64
import copy
import json
import math
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.normpath(os.path.join(HERE, "..", "..", "tests", "data", "hostile"))

# ---------------------------------------------------------------- a small valid skinned model


def f32s(*xs):
    return struct.pack("<%df" % len(xs), *xs)


def base():
    """A valid model: one skinned triangle (2 joints), one rotation animation."""
    parts = []  # (name, bytes)
    parts.append(("pos", f32s(0, 0, 0, 1, 0, 0, 0, 1, 0)))
    parts.append(("idx", struct.pack("<3H", 0, 1, 2) + b"\0\0"))
    parts.append(("joints", bytes([0, 1, 0, 0] * 3)))
    parts.append(("weights", f32s(*([0.5, 0.5, 0, 0] * 3))))
    ident = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]
    parts.append(("ibm", f32s(*(ident * 2))))
    parts.append(("times", f32s(0.0, 1.0)))
    parts.append(("rot", f32s(0, 0, 0, 1, 0, 0.7071068, 0, 0.7071068)))
    bin_ = b""
    views = []
    for _, data in parts:
        views.append({"buffer": 0, "byteOffset": len(bin_), "byteLength": len(data)})
        bin_ += data
    views[1]["byteLength"] = 6
    gltf = {
        "asset": {"version": "2.0", "generator": "dermis hostile-corpus"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [
            {"name": "root", "children": [1, 2]},
            {"name": "mesh", "mesh": 0, "skin": 0},
            {"name": "j0", "children": [3]},
            {"name": "j1", "translation": [0, 1, 0]},
        ],
        "meshes": [
            {
                "primitives": [
                    {
                        "attributes": {"POSITION": 0, "JOINTS_0": 2, "WEIGHTS_0": 3},
                        "indices": 1,
                    }
                ]
            }
        ],
        "skins": [{"joints": [2, 3], "inverseBindMatrices": 4}],
        "animations": [
            {
                "channels": [{"sampler": 0, "target": {"node": 3, "path": "rotation"}}],
                "samplers": [{"input": 5, "output": 6, "interpolation": "LINEAR"}],
            }
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"},
            {"bufferView": 2, "componentType": 5121, "count": 3, "type": "VEC4"},
            {"bufferView": 3, "componentType": 5126, "count": 3, "type": "VEC4"},
            {"bufferView": 4, "componentType": 5126, "count": 2, "type": "MAT4"},
            {"bufferView": 5, "componentType": 5126, "count": 2, "type": "SCALAR",
             "min": [0], "max": [1]},
            {"bufferView": 6, "componentType": 5126, "count": 2, "type": "VEC4"},
        ],
        "bufferViews": views,
        "buffers": [{"byteLength": len(bin_)}],
    }
    return gltf, bytearray(bin_)


OFFSETS = {}  # part name -> byte offset in the base BIN


def _offsets():
    g, _ = base()
    for name, v in zip(["pos", "idx", "joints", "weights", "ibm", "times", "rot"], g["bufferViews"]):
        OFFSETS[name] = v["byteOffset"]


_offsets()


def pad4(b, fill):
    return b + fill * ((4 - len(b) % 4) % 4)


def glb(gltf, bin_, version=2):
    j = pad4(json.dumps(gltf, separators=(",", ":")).encode(), b" ")
    out = struct.pack("<II", len(j), 0x4E4F534A) + j
    if bin_ is not None:
        b = pad4(bytes(bin_), b"\0")
        out += struct.pack("<II", len(b), 0x004E4942) + b
    return b"glTF" + struct.pack("<II", version, 12 + len(out)) + out


def gltf_embedded(gltf, bin_):
    g = copy.deepcopy(gltf)
    g["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64.b64encode(bytes(bin_)).decode()
    return json.dumps(g, indent=1).encode()


def with_uri(uri):
    g, b = base()
    g["buffers"][0]["uri"] = uri
    return json.dumps(g, indent=1).encode()


def mutate(fn, kind="glb"):
    g, b = base()
    r = fn(g, b)
    if isinstance(r, tuple):
        g, b = r
    return glb(g, b) if kind == "glb" else gltf_embedded(g, b)


def png_header(w, h):
    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)

    ihdr = struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(b"\0" * 64)) + chunk(b"IEND", b"")


def png_rgba(w, h, rgba):
    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)

    raw = b"".join(b"\0" + bytes(rgba) * w for _ in range(h))
    ihdr = struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b"")


def with_image(img):
    def f(g, b):
        off = len(b)
        b += img
        g["bufferViews"].append({"buffer": 0, "byteOffset": off, "byteLength": len(img)})
        g["buffers"][0]["byteLength"] = len(b)
        g["images"] = [{"bufferView": len(g["bufferViews"]) - 1, "mimeType": "image/png"}]
        g["textures"] = [{"source": 0}]
        g["materials"] = [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]
        g["meshes"][0]["primitives"][0]["material"] = 0
        return g, b

    return f


def put_f32(b, at, *xs):
    b[at:at + 4 * len(xs)] = f32s(*xs)


# ---------------------------------------------------------------- the corpus

CASES = []  # (file name, bytes, expected substring, "error" | "warning")


def case(name, data, expect, outcome="error"):
    CASES.append((name, data, expect, outcome))


valid = glb(*base())

# Container-level corruption.
case("empty.glb", b"", "empty file")
case("truncated_header.glb", b"glTF\x02\x00\x00\x00", "truncated GLB header")
case("bad_version.glb", glb(*base(), version=1), "unsupported GLB version 1")
case("length_beyond_file.glb", valid[:8] + struct.pack("<I", len(valid) + 100) + valid[12:], "truncated GLB")
case("truncated_mid_json.glb", valid[:8] + struct.pack("<I", 40) + valid[12:40], "truncated GLB chunk 0")
case("chunk_length_4gb.glb", valid[:12] + struct.pack("<I", 0xFFFFFFF0) + valid[16:], "truncated GLB chunk 0")
case("first_chunk_bin.glb", valid[:16] + struct.pack("<I", 0x004E4942) + valid[20:], "first GLB chunk is not JSON")
cut = len(valid) - 40
case("truncated_bin.glb", valid[:8] + struct.pack("<I", cut) + valid[12:cut], "truncated GLB chunk 1")
case("no_bin_chunk.glb", glb(base()[0], None), "no GLB BIN chunk")

# JSON-level corruption.
case("invalid_json.gltf", b'{"asset": {"version": "2.0"', "invalid JSON")
case("json_array.gltf", b"[1, 2, 3]", "invalid JSON")
case("json_deep_nesting.gltf", b"[" * 10000 + b"]" * 10000, "invalid JSON")
case("binary_garbage.gltf", bytes(range(256)) * 4, "invalid JSON")
case("skin_missing_node.glb", mutate(lambda g, b: g["skins"][0]["joints"].__setitem__(1, 99)), "skins[0].joints[1]")
case("accessor_missing_view.glb", mutate(lambda g, b: g["accessors"][0].__setitem__("bufferView", 42)), "accessors[0].bufferView")
case("unsupported_extension.gltf",
     mutate(lambda g, b: g.update(extensionsRequired=["KHR_draco_mesh_compression"], extensionsUsed=["KHR_draco_mesh_compression"]), "gltf"),
     "KHR_draco_mesh_compression\": Unsupported extension")

# Sizes and ranges.
case("buffer_4gb.glb", mutate(lambda g, b: g["buffers"][0].__setitem__("byteLength", 4_000_000_000)), "above the limit")
case("buffers_total_too_big.gltf",
     json.dumps({"asset": {"version": "2.0"}, "buffers": [{"byteLength": 200 << 20, "uri": "a.bin"}, {"byteLength": 200 << 20, "uri": "b.bin"}]}).encode(),
     "buffer 1: byteLength 209715200 brings the total above the limit")
case("buffer_longer_than_bin.glb", mutate(lambda g, b: g["buffers"][0].__setitem__("byteLength", len(b) + 64)), "only")
case("bufferview_out_of_buffer.glb", mutate(lambda g, b: g["bufferViews"][0].__setitem__("byteOffset", 10_000)), "bufferView 0 out of bounds")
case("bufferview_offset_2e53.glb", mutate(lambda g, b: g["bufferViews"][0].__setitem__("byteOffset", 2 ** 53)), "bufferView 0 out of bounds")
case("accessor_count_past_view.glb", mutate(lambda g, b: [g["accessors"][i].__setitem__("count", 1000) for i in (0, 2, 3)]), "out of bounds")
case("accessor_offset_past_view.glb", mutate(lambda g, b: g["accessors"][3].__setitem__("byteOffset", 40)), "out of bounds")
case("vertex_count_huge.glb",
     mutate(lambda g, b: [a.__setitem__("count", 100_000_000) for a in g["accessors"][:4]]),
     "too many vertices: above the limit")
case("key_count_huge.glb",
     mutate(lambda g, b: [g["accessors"][i].__setitem__("count", 100_000_000) for i in (5, 6)]),
     "count 100000000 above the limit")
case("animation_target_missing_node.glb",
     mutate(lambda g, b: g["animations"][0]["channels"][0]["target"].__setitem__("node", 77)),
     "animation 0 channel 0 targets missing node 77")
case("animation_bad_path.glb",
     mutate(lambda g, b: g["animations"][0]["channels"][0]["target"].__setitem__("path", "rotatio")),
     "invalid target path")
case("stride_smaller_than_element.glb", mutate(lambda g, b: g["bufferViews"][0].__setitem__("byteStride", 4)), "smaller than the element size")
case("stride_past_view.glb", mutate(lambda g, b: g["bufferViews"][0].__setitem__("byteStride", 252)), "out of bounds")
case("attribute_counts_differ.glb", mutate(lambda g, b: g["accessors"][3].__setitem__("count", 2)), "accessor counts differ")

# URIs.
case("data_uri_bad_base64.gltf", with_uri("data:application/octet-stream;base64,AAAA@@@@"), "malformed base64")
case("data_uri_not_base64.gltf", with_uri("data:application/octet-stream,hello"), "only base64")
case("data_uri_no_comma.gltf", with_uri("data:application/octet-stream;base64"), "malformed data URI")
case("data_uri_too_short.gltf", with_uri("data:application/octet-stream;base64,AAAA"), "only 3 bytes of data")
case("uri_parent_dir.gltf", with_uri("../secret.bin"), "escapes the model's folder")
case("uri_nested_parent_dir.gltf", with_uri("sub/../../secret.bin"), "escapes the model's folder")
case("uri_encoded_parent_dir.gltf", with_uri("%2E%2E/secret.bin"), "escapes the model's folder")
case("uri_absolute.gltf", with_uri("/etc/passwd"), "absolute path")
case("uri_file_scheme.gltf", with_uri("file:///etc/passwd"), "scheme")
case("uri_http.gltf", with_uri("http://example.com/model.bin"), "scheme")
case("uri_drive_letter.gltf", with_uri("C:\\models\\model.bin"), "drive letter")
case("uri_missing_file.gltf", with_uri("missing.bin"), "external file \"missing.bin\" not found")

# Vertex data.
case("joint_index_out_of_range.glb", mutate(lambda g, b: b.__setitem__(OFFSETS["joints"] + 1, 5)), "joint index 5 out of range")
case("nan_position.glb", mutate(lambda g, b: put_f32(b, OFFSETS["pos"] + 4, math.nan)), "NaN/Inf position")
case("inf_position.glb", mutate(lambda g, b: put_f32(b, OFFSETS["pos"], math.inf)), "NaN/Inf position")
case("nan_weight.glb", mutate(lambda g, b: put_f32(b, OFFSETS["weights"], math.nan)), "NaN/Inf or negative weights")
case("negative_weight.glb", mutate(lambda g, b: put_f32(b, OFFSETS["weights"] + 16, -1.0)), "NaN/Inf or negative weights")
case("zero_sum_weights.glb", mutate(lambda g, b: put_f32(b, OFFSETS["weights"] + 32, 0, 0, 0, 0)), "vertex 2 has zero-sum weights")
case("index_out_of_range.glb", mutate(lambda g, b: b.__setitem__(slice(OFFSETS["idx"] + 2, OFFSETS["idx"] + 4), struct.pack("<H", 7))), "index 7 (at 1)")
case("index_count_not_triangles.glb", mutate(lambda g, b: g["accessors"][1].__setitem__("count", 2)), "not a multiple of 3")
case("indices_float.glb", mutate(lambda g, b: g["accessors"][1].__setitem__("componentType", 5126)), "not allowed here")
case("weights_without_joints.glb", mutate(lambda g, b: g["meshes"][0]["primitives"][0]["attributes"].pop("JOINTS_0")), "WEIGHTS_0 but no JOINTS_0")
case("position_wrong_type.glb", mutate(lambda g, b: g["accessors"][0].__setitem__("type", "VEC2")), "must be VEC3")
case("sparse_index_out_of_range.glb",
     mutate(lambda g, b: g["accessors"][0].__setitem__("sparse", {"count": 1, "indices": {"bufferView": 1, "componentType": 5123}, "values": {"bufferView": 0}})
            or b.__setitem__(slice(OFFSETS["idx"], OFFSETS["idx"] + 2), struct.pack("<H", 9))),
     "sparse index 9 out of range")

# Hierarchy and skins.
def cycle(g, b):
    g["nodes"] += [{"name": "a", "children": [5]}, {"name": "b", "children": [4]}]


case("node_cycle.glb", mutate(cycle), "node cycle")
case("node_own_child.glb", mutate(lambda g, b: g["nodes"][3].__setitem__("children", [3])), "node cycle")
case("node_two_parents.glb", mutate(lambda g, b: g["nodes"][3].__setitem__("children", [1])), "node 1 has two parents")
case("scene_root_has_parent.glb", mutate(lambda g, b: g["scenes"][0]["nodes"].append(3)), "root node 3 has a parent")


def many_joints(g, b):
    first = len(g["nodes"])
    g["nodes"] += [{"name": "j%d" % i} for i in range(300)]
    g["nodes"][0]["children"] += list(range(first, first + 300))
    g["skins"][0] = {"joints": list(range(first, first + 300))}


case("skin_300_joints.glb", mutate(many_joints), "300 joints, more than the maximum 256")
case("skin_ibm_count_mismatch.glb", mutate(lambda g, b: g["accessors"][4].__setitem__("count", 1)), "inverseBindMatrices has 1 matrices for 2 joints")

# Animations.
case("sampler_count_mismatch.glb", mutate(lambda g, b: g["accessors"][5].__setitem__("count", 1)), "input/output count mismatch")
case("key_times_decreasing.glb", mutate(lambda g, b: put_f32(b, OFFSETS["times"], 2.0)), "not strictly increasing")
case("key_times_repeated.glb", mutate(lambda g, b: put_f32(b, OFFSETS["times"], 1.0)), "not strictly increasing")
case("key_time_negative.glb", mutate(lambda g, b: put_f32(b, OFFSETS["times"], -1.0)), "negative or NaN")
case("key_time_nan.glb", mutate(lambda g, b: put_f32(b, OFFSETS["times"] + 4, math.nan)), "negative or NaN")
case("cubic_sampler_short.glb", mutate(lambda g, b: g["animations"][0]["samplers"][0].__setitem__("interpolation", "CUBICSPLINE")), "expected 6")

# Images: a texture that does not decode is dropped with a warning; the model loads.
case("image_garbage.glb", mutate(with_image(b"\x89PNG\r\n\x1a\n" + b"\xff" * 64)),
     "baseColorTexture (texture 0): image 0: cannot decode image", "warning")
case("image_not_an_image.glb", mutate(with_image(b"GIF89a? no" * 8)), "image 0: cannot decode image", "warning")
case("image_100000px.glb", mutate(with_image(png_header(100000, 100000))), "image 0: cannot decode image", "warning")


# Materials: every bad value gets one warning naming the material and the value, and a fallback.
def with_material(mat, extra=None):
    def f(g, b):
        g["materials"] = [mat]
        g["meshes"][0]["primitives"][0]["material"] = 0
        if extra:
            extra(g)
        return g, b

    return mutate(f, "gltf")


def volume(**kw):
    return {"name": "Skin", "extensions": {"KHR_materials_volume": kw}}


def scatter(**kw):
    return {"name": "Skin", "extensions": {"KHR_materials_volume_scatter": kw}}


case("material_negative_attenuation_distance.gltf", with_material(volume(attenuationDistance=-1.0)),
     'material 0 "Skin": KHR_materials_volume.attenuationDistance = -1 is not > 0; inf is used', "warning")
case("material_attenuation_colour_above_one.gltf", with_material(volume(attenuationColor=[1.5, 0.5, 0.25])),
     "KHR_materials_volume.attenuationColor = [1.5, 0.5, 0.25] is outside [0, 1]; clamped to [1.0, 0.5, 0.25]",
     "warning")
case("material_attenuation_colour_not_numbers.gltf", with_material(volume(attenuationColor="red")),
     'KHR_materials_volume.attenuationColor = "red" is not three numbers', "warning")
case("material_thickness_negative.gltf", with_material(volume(thicknessFactor=-0.5)),
     "KHR_materials_volume.thicknessFactor = -0.5 is not ≥ 0; 0 is used", "warning")
case("material_ior_below_one.gltf",
     with_material({"name": "Skin", "extensions": {"KHR_materials_ior": {"ior": 0.5}}}),
     "KHR_materials_ior.ior = 0.5 is not ≥ 1; 1.5 is used", "warning")
case("material_anisotropy_one.gltf", with_material(scatter(scatterAnisotropy=1.0)),
     "KHR_materials_volume_scatter.scatterAnisotropy = 1 is not in (−1, 1); 0 is used", "warning")
case("material_multiscatter_negative.gltf", with_material(scatter(multiscatterColor=[-0.5, 0.5, 0.5])),
     "KHR_materials_volume_scatter.multiscatterColor = [-0.5, 0.5, 0.5] is outside [0, 1]", "warning")
case("material_unknown_property.gltf", with_material(scatter(scatterFoo=1)),
     "KHR_materials_volume_scatter.scatterFoo is not a known property; ignored", "warning")
case("material_extension_not_object.gltf",
     with_material({"name": "Skin", "extensions": {"KHR_materials_volume": [1, 2]}}),
     "KHR_materials_volume = [1,2] is not an object; extension ignored", "warning")
case("material_texture_missing.gltf",
     with_material({"name": "Shirt", "pbrMetallicRoughness": {"baseColorTexture": {"index": 7}}}),
     'material 0 "Shirt": baseColorTexture references texture 7, but the file has 0; texture ignored', "warning")
case("material_extension_texture_missing.gltf", with_material(scatter(multiscatterColorTexture={"index": 9})),
     "KHR_materials_volume_scatter.multiscatterColorTexture references texture 9, but the file has 0", "warning")
case("material_extension_texture_not_a_reference.gltf",
     with_material(scatter(multiscatterColorTexture={"index": -1})),
     "multiscatterColorTexture = {\"index\":-1} is not a texture reference; texture ignored", "warning")
case("material_texcoord_1.gltf",
     mutate(lambda g, b: with_image(png_rgba(2, 2, [9, 9, 9, 255]))(g, b) and g["materials"][0].update(
         occlusionTexture={"index": 0, "texCoord": 1}), "gltf"),
     "occlusionTexture uses TEXCOORD_1 (only TEXCOORD_0 is loaded); texture ignored", "warning")
case("material_unknown_alpha_mode.gltf", with_material({"name": "Shirt", "alphaMode": "DITHER"}),
     'material 0 "Shirt": unknown alphaMode; OPAQUE is used', "warning")
case("material_roughness_above_one.gltf",
     with_material({"name": "Shirt", "pbrMetallicRoughness": {"roughnessFactor": 1.5}}),
     "roughnessFactor = 1.5 is outside [0, 1]; clamped to 1", "warning")
case("material_base_colour_infinite.gltf",
     with_material({"name": "Shirt", "pbrMetallicRoughness": {"baseColorFactor": [1e39, 0.5, 0.5, 1]}}),
     "baseColorFactor = [inf, 0.5, 0.5, 1.0] is not finite; the default is used", "warning")
case("material_emissive_strength_negative.gltf",
     with_material({"name": "Lamp", "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": -2}}}),
     "KHR_materials_emissive_strength.emissiveStrength = -2 is not ≥ 0; 1 is used", "warning")
case("material_extension_unsupported.gltf",
     with_material({"name": "Velvet", "extensions": {"KHR_materials_sheen": {"sheenColorFactor": [1, 0, 0]}}}),
     "material extensions not supported, ignored: KHR_materials_sheen", "warning")



# ---------------------------------------------------------------- valid fixtures (tests/data)


def rich():
    """The base model plus UVs, _THICKNESS, u16 joints, normalized u8 weights, a STEP and a
    CUBICSPLINE channel and a base colour factor: the valid fixture the Rust tests check."""
    g, b = base()

    def add(data, acc):
        off = len(b)
        b.extend(pad4(data, b"\0"))
        g["bufferViews"].append({"buffer": 0, "byteOffset": off, "byteLength": len(data)})
        acc["bufferView"] = len(g["bufferViews"]) - 1
        g["accessors"].append(acc)
        return len(g["accessors"]) - 1

    attrs = g["meshes"][0]["primitives"][0]["attributes"]
    attrs["TEXCOORD_0"] = add(f32s(0, 0, 1, 0, 0, 1), {"componentType": 5126, "count": 3, "type": "VEC2"})
    attrs["_THICKNESS"] = add(f32s(0.001, 0.002, 0.003), {"componentType": 5126, "count": 3, "type": "SCALAR"})
    attrs["JOINTS_0"] = add(struct.pack("<12H", *([1, 0, 0, 0] * 3)), {"componentType": 5123, "count": 3, "type": "VEC4"})
    attrs["WEIGHTS_0"] = add(bytes([255, 0, 0, 0, 128, 127, 0, 0, 51, 51, 51, 51]),
                             {"componentType": 5121, "normalized": True, "count": 3, "type": "VEC4"})
    t_step = add(f32s(0.0, 0.5), {"componentType": 5126, "count": 2, "type": "SCALAR", "min": [0], "max": [0.5]})
    v_step = add(f32s(0, 1, 0, 0, 2, 0), {"componentType": 5126, "count": 2, "type": "VEC3"})
    t_cub = add(f32s(0.0, 2.0), {"componentType": 5126, "count": 2, "type": "SCALAR", "min": [0], "max": [2]})
    # in-tangent, value, out-tangent per key
    v_cub = add(f32s(0, 0, 0, 1, 1, 1, 1, 0, 0, 0, 0, 0, 2, 2, 2, 0, 0, 0),
                {"componentType": 5126, "count": 6, "type": "VEC3"})
    anim = g["animations"][0]
    anim["samplers"] += [{"input": t_step, "output": v_step, "interpolation": "STEP"},
                         {"input": t_cub, "output": v_cub, "interpolation": "CUBICSPLINE"}]
    anim["channels"] += [{"sampler": 1, "target": {"node": 2, "path": "translation"}},
                         {"sampler": 2, "target": {"node": 2, "path": "scale"}}]
    g["materials"] = [{"name": "skin", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.6, 0.5, 1.0]}}]
    g["meshes"][0]["primitives"][0]["material"] = 0
    g["buffers"][0]["byteLength"] = len(b)
    return g, b


def fixtures():
    data = os.path.normpath(os.path.join(OUT, ".."))
    g, b = rich()
    with open(os.path.join(data, "skinned.glb"), "wb") as f:
        f.write(glb(g, b))
    with open(os.path.join(data, "embedded.gltf"), "wb") as f:
        f.write(gltf_embedded(g, b))
    ext = os.path.join(data, "external")
    os.makedirs(ext, exist_ok=True)
    g = copy.deepcopy(g)
    g["buffers"][0]["uri"] = "model%20data.bin"  # percent-encoded space
    g["images"] = [{"uri": "textures/skin.png"}]
    g["textures"] = [{"source": 0}]
    g["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {"index": 0}
    with open(os.path.join(ext, "model.gltf"), "w") as f:
        f.write(json.dumps(g, indent=1))
    with open(os.path.join(ext, "model data.bin"), "wb") as f:
        f.write(bytes(b))
    os.makedirs(os.path.join(ext, "textures"), exist_ok=True)
    with open(os.path.join(ext, "textures", "skin.png"), "wb") as f:
        f.write(png_rgba(4, 2, [200, 150, 120, 255]))


MATERIAL_FIXTURES = {}  # file name under tests/data/materials -> JSON


def data_uri_png(rgba, w=2, h=2):
    return "data:image/png;base64," + base64.b64encode(png_rgba(w, h, rgba)).decode()


def material_fixtures():
    """Valid files declaring every material field the loader reads (tests/asset_materials.rs)."""
    g, b = rich()
    g = copy.deepcopy(g)
    g["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64.b64encode(bytes(b)).decode()
    prim = g["meshes"][0]["primitives"][0]
    g["images"] = [{"uri": data_uri_png([200, 100, 50, 128])}, {"uri": data_uri_png([10, 128, 250, 255])}]
    g["textures"] = [{"source": 0}, {"source": 1}]

    # pbr.gltf: three primitives of one mesh, three materials; image 0 is read as colour
    # (base colour, emissive) and as data (occlusion), image 1 as data only.
    pbr = copy.deepcopy(g)
    pbr["meshes"][0]["primitives"] = [dict(prim, material=i) for i in range(3)]
    pbr["extensionsUsed"] = ["KHR_materials_emissive_strength"]
    pbr["materials"] = [
        {"name": "Metal", "doubleSided": True,
         "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.8, 0.7, 1.0], "baseColorTexture": {"index": 0},
                                  "metallicFactor": 0.75, "roughnessFactor": 0.25,
                                  "metallicRoughnessTexture": {"index": 1}},
         "normalTexture": {"index": 1, "scale": 0.5},
         "occlusionTexture": {"index": 0, "strength": 0.6},
         "emissiveFactor": [0.1, 0.2, 0.3], "emissiveTexture": {"index": 0},
         "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4.0}}},
        {"name": "Leaves", "alphaMode": "MASK", "alphaCutoff": 0.3,
         "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}},
        {"name": "Glass", "alphaMode": "BLEND"},
    ]
    MATERIAL_FIXTURES["pbr.gltf"] = pbr

    # skin.gltf: the four extensions (the draft's `multiscatterColor`), a material with the
    # draft's earlier `scatterAlbedo`, one with volume and diffuse transmission only, cloth.
    skin = copy.deepcopy(g)
    skin["meshes"][0]["primitives"] = [dict(prim, material=i) for i in range(4)]
    skin["extensionsUsed"] = ["KHR_materials_volume", "KHR_materials_volume_scatter",
                              "KHR_materials_diffuse_transmission", "KHR_materials_ior"]
    skin["materials"] = [
        {"name": "Face", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.6, 0.5, 1.0], "metallicFactor": 0},
         "extensions": {
             "KHR_materials_volume": {"thicknessFactor": 0.02, "thicknessTexture": {"index": 1},
                                      "attenuationDistance": 0.002, "attenuationColor": [0.5, 0.25, 0.125]},
             "KHR_materials_volume_scatter": {"multiscatterColor": [0.8, 0.5, 0.3],
                                              "multiscatterColorTexture": {"index": 0},
                                              "scatterAnisotropy": 0.4},
             "KHR_materials_diffuse_transmission": {"diffuseTransmissionFactor": 0.7,
                                                    "diffuseTransmissionTexture": {"index": 1},
                                                    "diffuseTransmissionColorFactor": [1.0, 0.4, 0.3],
                                                    "diffuseTransmissionColorTexture": {"index": 0}},
             "KHR_materials_ior": {"ior": 1.4}}},
        {"name": "Wax", "extensions": {
            "KHR_materials_volume": {"thicknessFactor": 0.01, "attenuationDistance": 0.001,
                                     "attenuationColor": [0.5, 0.5, 0.5]},
            "KHR_materials_volume_scatter": {"scatterAlbedo": [0.9, 0.9, 0.9]}}},
        {"name": "Leaf", "extensions": {
            "KHR_materials_volume": {"thicknessFactor": 0.001},
            "KHR_materials_diffuse_transmission": {"diffuseTransmissionFactor": 0.5}}},
        {"name": "Skin shirt", "pbrMetallicRoughness": {"baseColorFactor": [0.1, 0.3, 0.6, 1.0]}},
    ]
    MATERIAL_FIXTURES["skin.gltf"] = skin

    # named.gltf: no extension declares skin; the name rule decides.
    named = copy.deepcopy(g)
    names = ["Body", "M_Skin_01", "HairBase", "Eyes", "BodySuit", "Skinny"]
    named["meshes"][0]["primitives"] = [dict(prim, material=i) for i in range(len(names))]
    named["materials"] = [{"name": n, "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}} for n in names]
    MATERIAL_FIXTURES["named.gltf"] = named

    out = os.path.normpath(os.path.join(OUT, "..", "materials"))
    os.makedirs(out, exist_ok=True)
    for name, doc in MATERIAL_FIXTURES.items():
        with open(os.path.join(out, name), "w") as f:
            f.write(json.dumps(doc, indent=1, ensure_ascii=False) + "\n")


def main():
    fixtures()
    material_fixtures()
    os.makedirs(OUT, exist_ok=True)
    for f in os.listdir(OUT):
        if f.endswith((".glb", ".gltf")) or f == "index.tsv":
            os.remove(os.path.join(OUT, f))
    names = set()
    with open(os.path.join(OUT, "index.tsv"), "w") as index:
        index.write("# file\texpected substring\toutcome: error | warning | none "
                    "(generated by tools/hostile-corpus/make.py)\n")
        for name, data, expect, outcome in CASES:
            assert name not in names, name
            names.add(name)
            with open(os.path.join(OUT, name), "wb") as f:
                f.write(data)
            index.write("%s\t%s\t%s\n" % (name, expect, outcome))
    print("wrote %d files to %s" % (len(CASES), OUT))


if __name__ == "__main__":
    main()
