#!/usr/bin/python3
"""Writes the seed corpus of the loader fuzzers (fuzz/, docs/hardening.md, Fuzzing).

make-fuzz-corpus.py --kind gltf|scene_json|all --out DIR

gltf seeds: small valid models (triangle, cube; .gltf with base64 buffers and .glb; strips,
fans, sparse accessors, a camera, an alpha-masked texture, the glTF files of data/stability)
and malformed variants of them: truncated, huge counts, out-of-range indices, cyclic and doubly
listed nodes, deep node chains, NaN/Inf, bad base64, wrong GLB chunk lengths, bad magic, float
index accessors, huge byteStride, deep JSON nesting, external URIs; images (PNG and JPEG, in
GLB buffer views and data: URIs) and their hostile variants: views past their buffer, headers
claiming past the texture limits, negative offsets, values infinite as float, malformed material
keys, required extensions.
scene_json seeds: every data/*.json and data/stability/*.json, and malformed variants.
Standard library only; the output is deterministic.
"""
import argparse
import base64
import json
import pathlib
import struct
import zlib

ROOT = pathlib.Path(__file__).resolve().parent.parent

FLOAT, UINT, USHORT, UBYTE, SHORT = 5126, 5125, 5123, 5121, 5122


def data_uri(raw):
    return "data:application/octet-stream;base64," + base64.b64encode(raw).decode()


class Model:
    """A glTF document with one binary buffer, built view by view."""

    def __init__(self):
        self.buf = bytearray()
        self.doc = {"asset": {"version": "2.0"}, "bufferViews": [], "accessors": []}

    def view(self, raw, stride=None):
        while len(self.buf) % 4:
            self.buf.append(0)
        v = {"buffer": 0, "byteOffset": len(self.buf), "byteLength": len(raw)}
        if stride:
            v["byteStride"] = stride
        self.buf += raw
        self.doc["bufferViews"].append(v)
        return len(self.doc["bufferViews"]) - 1

    def accessor(self, view, ctype, count, typ, **extra):
        a = {"bufferView": view, "componentType": ctype, "count": count, "type": typ}
        a.update(extra)
        self.doc["accessors"].append(a)
        return len(self.doc["accessors"]) - 1

    def positions(self, xyz):
        raw = struct.pack("<%df" % len(xyz), *xyz)
        n = len(xyz) // 3
        lo = [min(xyz[i::3]) for i in range(3)]
        hi = [max(xyz[i::3]) for i in range(3)]
        return self.accessor(self.view(raw), FLOAT, n, "VEC3", min=lo, max=hi)

    def indices(self, idx, ctype=USHORT):
        fmt = {UBYTE: "B", USHORT: "H", UINT: "I"}[ctype]
        return self.accessor(self.view(struct.pack("<%d%s" % (len(idx), fmt), *idx)), ctype,
                             len(idx), "SCALAR")

    def mesh(self, prims, nodes=None, scene=True):
        self.doc["meshes"] = [{"primitives": prims}]
        self.doc["nodes"] = nodes if nodes is not None else [{"mesh": 0}]
        if scene:
            self.doc["scene"] = 0
            self.doc["scenes"] = [{"nodes": [0]}]

    def gltf(self):
        d = json.loads(json.dumps(self.doc))
        d["buffers"] = [{"byteLength": len(self.buf), "uri": data_uri(bytes(self.buf))}]
        return json.dumps(d, separators=(",", ":")).encode()

    def glb(self):
        d = json.loads(json.dumps(self.doc))
        d["buffers"] = [{"byteLength": len(self.buf)}]
        return glb(json.dumps(d, separators=(",", ":")).encode(), bytes(self.buf))


def pad(raw, fill):
    return raw + fill * (-len(raw) % 4)


def glb(json_bytes, bin_bytes=None, version=2):
    j = pad(json_bytes, b" ")
    out = struct.pack("<I4s", len(j), b"JSON") + j
    if bin_bytes is not None:
        b = pad(bin_bytes, b"\0")
        out += struct.pack("<I4s", len(b), b"BIN\0") + b
    return b"glTF" + struct.pack("<II", version, 12 + len(out)) + out


def png(width, height, rgba):
    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(
            ">I", zlib.crc32(kind + body) & 0xFFFFFFFF)
    rows = b"".join(b"\0" + rgba[y * width * 4:(y + 1) * width * 4] for y in range(height))
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))


# A 4 x 2 baseline JPEG of one colour (200, 100, 50), as stb_image_write writes it at quality 50.
JPEG_4X2 = bytes.fromhex(
    "ffd8ffe000104a46494600010100000100010000ffdb008400100b0c0e0c0a100e0d0e1211101318281a181616"
    "183123251d283a333d3c3933383740485c4e404457453738506d51575f626768673e4d71797064785c65676301"
    "1112121815182f1a1a2f6342384263636363636363636363636363636363636363636363636363636363636363"
    "63636363636363636363636363636363636363ffc00011080002000403012200021101031101ffc401a2000001"
    "0501010101010100000000000000000102030405060708090a0b100002010303020403050504040000017d0102"
    "0300041105122131410613516107227114328191a1082342b1c11552d1f02433627282090a161718191a252627"
    "28292a3435363738393a434445464748494a535455565758595a636465666768696a737475767778797a838485"
    "868788898a92939495969798999aa2a3a4a5a6a7a8a9aab2b3b4b5b6b7b8b9bac2c3c4c5c6c7c8c9cad2d3d4d5"
    "d6d7d8d9dae1e2e3e4e5e6e7e8e9eaf1f2f3f4f5f6f7f8f9fa0100030101010101010101010000000000000102"
    "030405060708090a0b110002010204040304070504040001027700010203110405213106124151076171132232"
    "8108144291a1b1c109233352f0156272d10a162434e125f11718191a262728292a35363738393a434445464748"
    "494a535455565758595a636465666768696a737475767778797a82838485868788898a92939495969798999aa2"
    "a3a4a5a6a7a8a9aab2b3b4b5b6b7b8b9bac2c3c4c5c6c7c8c9cad2d3d4d5d6d7d8d9dae2e3e4e5e6e7e8e9eaf2"
    "f3f4f5f6f7f8f9faffda000c03010002110311003f006d14515e59ec9fffd9")

TRI = [0, 0, 0, 1, 0, 0, 0, 1, 0]
CUBE = [x for i in range(8) for x in ((i & 1) * 1.0, (i >> 1 & 1) * 1.0, (i >> 2 & 1) * 1.0)]
CUBE_IDX = [0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
            2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5]


def triangle():
    m = Model()
    p = m.positions(TRI)
    i = m.indices([0, 1, 2])
    m.mesh([{"attributes": {"POSITION": p}, "indices": i}])
    return m


def cube(ctype=UINT):
    m = Model()
    p = m.positions(CUBE)
    i = m.indices(CUBE_IDX, ctype)
    m.mesh([{"attributes": {"POSITION": p}, "indices": i}])
    return m


def edited(model, edit):
    """A copy of `model` with edit(doc) applied to its JSON."""
    m = Model()
    m.buf = bytearray(model.buf)
    m.doc = json.loads(json.dumps(model.doc))
    edit(m.doc)
    return m


def gltf_seeds():
    seeds = {}
    t, c = triangle(), cube()
    seeds["triangle.gltf"] = t.gltf()
    seeds["triangle.glb"] = t.glb()
    seeds["cube.gltf"] = c.gltf()
    seeds["cube.glb"] = c.glb()
    seeds["cube-u8.gltf"] = cube(UBYTE).gltf()

    # Strips, fans, non-indexed, interleaved stride, sparse, hierarchy, camera.
    m = Model()
    p = m.positions([0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 0, 2, 0])
    m.mesh([{"attributes": {"POSITION": p}, "mode": 5},
            {"attributes": {"POSITION": p}, "mode": 6},
            {"attributes": {"POSITION": p}, "indices": m.indices([0, 1, 2, 2, 1, 3], UINT)}])
    seeds["strip-fan.gltf"] = m.gltf()
    m = Model()
    raw = b"".join(struct.pack("<3f4x", *TRI[k:k + 3]) for k in range(0, 9, 3))
    p = m.accessor(m.view(raw, stride=16), FLOAT, 3, "VEC3")
    m.mesh([{"attributes": {"POSITION": p}}])
    seeds["stride16.gltf"] = m.gltf()
    m = triangle()
    iv = m.view(struct.pack("<B3x", 1))
    vv = m.view(struct.pack("<3f", 2, 0, 0))
    m.doc["accessors"][0]["sparse"] = {"count": 1, "indices": {"bufferView": iv, "componentType": UBYTE},
                                       "values": {"bufferView": vv}}
    seeds["sparse.gltf"] = m.gltf()
    m = edited(triangle(), lambda d: d.update(
        nodes=[{"children": [1], "translation": [1, 2, 3], "rotation": [0, 0.7071, 0, 0.7071]},
               {"mesh": 0, "scale": [2, 2, 2]},
               {"camera": 0, "translation": [0, 0, 5]},
               {"camera": 1}],
        scenes=[{"nodes": [0, 2, 3]}],
        cameras=[{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}},
                 {"type": "orthographic", "orthographic": {"xmag": 1, "ymag": 1, "znear": 0.1, "zfar": 9}}]))
    seeds["hierarchy-camera.gltf"] = m.gltf()
    m = edited(triangle(), lambda d: d["nodes"][0].update(
        matrix=[-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]))
    seeds["mirrored-matrix.gltf"] = m.gltf()

    # Alpha-masked texture with a sampler and KHR_texture_transform.
    m = Model()
    p = m.positions(TRI)
    uv = m.accessor(m.view(struct.pack("<6f", 0, 0, 1, 0, 0, 1)), FLOAT, 3, "VEC2")
    image = png(2, 2, bytes([255, 0, 0, 255, 0, 255, 0, 0, 0, 0, 255, 255, 255, 255, 255, 0]))
    m.mesh([{"attributes": {"POSITION": p, "TEXCOORD_0": uv}, "material": 0}])
    m.doc.update(
        materials=[{"name": "leaf", "alphaMode": "MASK", "alphaCutoff": 0.4, "doubleSided": True,
                    "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "baseColorTexture": {
                        "index": 0, "extensions": {"KHR_texture_transform": {
                            "offset": [0, 1], "rotation": 1.57, "scale": [0.5, 0.5]}}}}}],
        textures=[{"source": 0, "sampler": 0}],
        samplers=[{"wrapS": 33071, "wrapT": 33648}],
        images=[{"uri": "data:image/png;base64," + base64.b64encode(image).decode()}],
        extensionsUsed=["KHR_texture_transform"])
    seeds["alpha-texture.gltf"] = m.gltf()
    textured = m

    # The same triangle with its image inside the buffer (as levels come: images in the GLB's
    # BIN chunk), as PNG and as JPEG, and a JPEG data: URI.
    def with_image_view(raw, mime):
        m2 = edited(textured, lambda d: None)
        v = m2.view(raw)
        m2.doc["images"] = [{"bufferView": v, "mimeType": mime}]
        return m2
    textured_png_view = with_image_view(image, "image/png")
    seeds["alpha-texture-png.glb"] = textured_png_view.glb()
    textured_jpeg_view = with_image_view(JPEG_4X2, "image/jpeg")
    seeds["alpha-texture-jpeg.glb"] = textured_jpeg_view.glb()
    m = edited(textured, lambda d: d["images"][0].update(
        uri="data:image/jpeg;base64," + base64.b64encode(JPEG_4X2).decode()))
    seeds["alpha-texture-jpeg.gltf"] = m.gltf()

    for f in sorted((ROOT / "data").rglob("*.gltf")) + sorted((ROOT / "data").rglob("*.glb")):
        seeds["data-" + f.name] = f.read_bytes()

    # ---- malformed ----
    bad = {}
    for name in ("triangle.gltf", "cube.glb", "alpha-texture.gltf"):
        whole = seeds[name]
        for frac in (2, 3, 5):
            bad["truncated-%d-%s" % (frac, name)] = whole[:len(whole) * (frac - 1) // frac]
    bad["empty"] = b""
    bad["bad-magic.glb"] = b"glTX" + t.glb()[4:]
    bad["glb-version1.glb"] = glb(json.dumps(t.doc).encode(), bytes(t.buf), version=1)
    g = bytearray(t.glb())
    g[12:16] = struct.pack("<I", 0x7FFFFFF0)
    bad["glb-json-chunk-overruns.glb"] = bytes(g)
    # The BIN chunk's length forgets its own 8-byte header, and the buffer claims all of it.
    d = json.loads(json.dumps(t.doc))
    d["buffers"] = [{"byteLength": len(pad(bytes(t.buf), b"\0")) + 8}]
    g = bytearray(glb(json.dumps(d, separators=(",", ":")).encode(), bytes(t.buf)))
    jl = struct.unpack("<I", g[12:16])[0]
    bin_at = 20 + jl
    g[bin_at:bin_at + 4] = struct.pack("<I", len(g) - bin_at)
    bad["glb-bin-chunk-overruns-by-8.glb"] = bytes(g)
    g = bytearray(t.glb())
    g[bin_at:bin_at + 4] = struct.pack("<I", 0xFFFFFFFC)
    bad["glb-bin-chunk-huge.glb"] = bytes(g)
    g = bytearray(t.glb())
    g[8:12] = struct.pack("<I", len(g) + 100)
    bad["glb-length-past-end.glb"] = bytes(g)
    bad["glb-no-bin.glb"] = glb(json.dumps(t.doc).encode())
    bad["glb-short-tail.glb"] = t.glb() + b"\0\0\0"

    def acc(i, **kv):
        return lambda d: d["accessors"][i].update(kv)

    for name, model, edit in [
        ("count-huge", t, acc(0, count=4294967295)),
        ("count-1e12", t, acc(0, count=10**12)),
        ("count-2p28", t, acc(0, count=2**28 + 1)),
        ("count-negative", t, acc(0, count=-1)),
        ("index-count-huge", t, acc(1, count=3 * 2**22)),
        ("index-float", t, acc(1, componentType=FLOAT)),
        ("index-vec3", t, acc(1, type="VEC3")),
        ("position-short", t, acc(0, componentType=SHORT)),
        ("position-view-missing", t, acc(0, bufferView=99)),
        ("position-no-view", t, lambda d: d["accessors"][0].pop("bufferView")),
        ("position-offset-huge", t, acc(0, byteOffset=2**40)),
        ("view-stride-huge", t, lambda d: d["bufferViews"][0].update(byteStride=2**31)),
        ("view-stride-252", t, lambda d: d["bufferViews"][0].update(byteStride=252)),
        ("view-stride-small", t, lambda d: d["bufferViews"][0].update(byteStride=4)),
        ("view-outside-buffer", t, lambda d: d["bufferViews"][0].update(byteOffset=4096)),
        ("view-buffer-missing", t, lambda d: d["bufferViews"][0].update(buffer=7)),
        ("mode-points", t, lambda d: d["meshes"][0]["primitives"][0].update(mode=0)),
        ("mode-99", t, lambda d: d["meshes"][0]["primitives"][0].update(mode=99)),
        ("no-position", t, lambda d: d["meshes"][0]["primitives"][0].update(attributes={})),
        ("mesh-missing", t, lambda d: d["nodes"][0].update(mesh=5)),
        ("material-missing", t, lambda d: d["meshes"][0]["primitives"][0].update(material=3)),
        ("scene-node-missing", t, lambda d: d["scenes"][0].update(nodes=[9])),
        ("scene-default-missing", t, lambda d: d.update(scene=4)),
        ("node-cycle", t, lambda d: d.update(nodes=[{"mesh": 0, "children": [1]}, {"children": [0]}])),
        ("node-self-child", t, lambda d: d.update(nodes=[{"mesh": 0, "children": [0]}])),
        ("node-chain-1200", t, lambda d: d.update(
            nodes=[{"mesh": 0, "children": [i + 1]} for i in range(1199)] + [{"mesh": 0}])),
        ("node-chain-doubled-40", t, lambda d: d.update(
            nodes=[{"mesh": 0, "children": [i + 1, i + 1]} for i in range(39)] + [{"mesh": 0}])),
        ("node-two-parents", t, lambda d: d.update(
            nodes=[{"children": [2]}, {"children": [2]}, {"mesh": 0}], scenes=[{"nodes": [0, 1]}])),
        ("node-matrix-inf", t, lambda d: d["nodes"][0].update(matrix=[1e308] * 16)),
        ("node-scale-huge", t, lambda d: d["nodes"][0].update(scale=[1e30, 1e30, 1e30])),
        ("node-rotation-zero", t, lambda d: d["nodes"][0].update(rotation=[0, 0, 0, 0])),
        ("number-1e999", t, lambda d: d["nodes"][0].update(translation=["1e999", 0, 0])),
        ("camera-yfov-bad", t, lambda d: d.update(nodes=[{"mesh": 0}, {"camera": 0}],
                                                    scenes=[{"nodes": [0, 1]}],
                                                    cameras=[{"type": "perspective",
                                                              "perspective": {"yfov": 7}}])),
        ("required-draco", t, lambda d: d.update(extensionsRequired=["KHR_draco_mesh_compression"])),
        ("sparse-index-out-of-range", t, lambda d: d["accessors"][0].update(
            sparse={"count": 1, "indices": {"bufferView": 1, "componentType": USHORT},
                    "values": {"bufferView": 0}})),
        ("sparse-count-huge", t, lambda d: d["accessors"][0].update(
            sparse={"count": 2**31 - 1, "indices": {"bufferView": 1, "componentType": UINT},
                    "values": {"bufferView": 0}})),
        ("texture-missing", textured, lambda d: d["materials"][0]["pbrMetallicRoughness"][
            "baseColorTexture"].update(index=5)),
        ("texture-transform-nan", textured, lambda d: d["materials"][0]["pbrMetallicRoughness"][
            "baseColorTexture"]["extensions"]["KHR_texture_transform"].update(rotation="x")),
        ("sampler-wrap-bad", textured, lambda d: d["samplers"][0].update(wrapS=7)),
        ("alpha-mode-bad", textured, lambda d: d["materials"][0].update(alphaMode="FOO")),
    ]:
        bad[name + ".gltf"] = edited(model, edit).gltf()

    def raw_doc(model, edit):
        d = json.loads(model.gltf())
        edit(d)
        return json.dumps(d, separators=(",", ":")).encode()

    nan = bytearray(t.buf)
    nan[0:4] = struct.pack("<f", float("nan"))
    m = triangle()
    m.buf = nan
    bad["position-nan.gltf"] = m.gltf()
    m.buf[0:4] = struct.pack("<f", float("inf"))
    bad["position-inf.glb"] = m.glb()
    m.buf[0:4] = struct.pack("<f", 3e38)
    bad["position-huge.gltf"] = m.gltf()
    m = triangle()
    m.buf[24:26] = struct.pack("<H", 60000)
    bad["index-out-of-range.gltf"] = m.gltf()
    bad["base64-bad.gltf"] = raw_doc(t, lambda d: d["buffers"][0].update(
        uri="data:application/octet-stream;base64,!!!!not*base64"))
    bad["base64-short.gltf"] = raw_doc(t, lambda d: d["buffers"][0].update(
        uri="data:application/octet-stream;base64,AAAA"))
    bad["buffer-bytelength-huge.gltf"] = raw_doc(t, lambda d: d["buffers"][0].update(
        byteLength=2**40))
    bad["image-bad-png.gltf"] = raw_doc(textured, lambda d: d["images"][0].update(
        uri="data:image/png;base64," + base64.b64encode(b"\x89PNG\r\n\x1a\nxxxx").decode()))
    huge_png = png(1, 1, b"\0\0\0\0").replace(struct.pack(">II", 1, 1), struct.pack(">II", 1 << 24, 1 << 24))
    bad["image-huge-dimensions.gltf"] = raw_doc(textured, lambda d: d["images"][0].update(
        uri="data:image/png;base64," + base64.b64encode(huge_png).decode()))
    # Images in buffer views out of range, header claims past the texture limits, values finite
    # as double only, malformed material keys, required extensions (tests/geometry/scene/
    # TextureHardeningTest.cpp has each as a regression test).
    pv = textured_png_view
    last = len(pv.doc["bufferViews"]) - 1
    for name, edit in [
        ("image-view-past-buffer", lambda d: d["bufferViews"][last].update(byteOffset=1 << 30)),
        ("image-view-long", lambda d: d["bufferViews"][last].update(byteLength=1 << 30)),
        ("image-view-missing", lambda d: d["images"][0].update(bufferView=99)),
        ("view-offset-negative", lambda d: d["bufferViews"][0].update(byteOffset=-12)),
        ("accessor-offset-negative", lambda d: d["accessors"][0].update(byteOffset=-4)),
        ("cutoff-negative", lambda d: d["materials"][0].update(alphaCutoff=-0.5)),
        ("factor-float-inf", lambda d: d["materials"][0]["pbrMetallicRoughness"].update(
            baseColorFactor=[1, 1, 1, 1e39])),
        ("transform-float-inf", lambda d: d["materials"][0]["pbrMetallicRoughness"]
         ["baseColorTexture"]["extensions"]["KHR_texture_transform"].update(scale=[1e39, 1])),
        ("pbr-factor-short", lambda d: d["materials"][0]["pbrMetallicRoughness"].update(
            baseColorFactor=[1, 1, 1])),
        ("draco-required", lambda d: d.update(extensionsRequired=["KHR_draco_mesh_compression"])),
        ("basisu-required", lambda d: (d.update(extensionsRequired=["KHR_texture_basisu"]),
                                       d["images"][0].update(mimeType="image/ktx2"))),
    ]:
        bad[name + ".glb"] = edited(pv, edit).glb()
    big_png = bytearray(image)
    big_png[16:24] = struct.pack(">II", 16385, 1)
    bad["image-png-wide.glb"] = with_image_view(bytes(big_png), "image/png").glb()
    giga_jpeg = bytes.fromhex("ffd8ffc0001108fde8fde803011100021101031101ffd9")
    bad["image-jpeg-gigapixel.glb"] = with_image_view(giga_jpeg, "image/jpeg").glb()
    bad["image-jpeg-gigapixel.gltf"] = raw_doc(textured, lambda d: d["images"][0].update(
        uri="data:image/jpeg;base64," + base64.b64encode(giga_jpeg).decode()))
    bad["image-jpeg-truncated.glb"] = with_image_view(JPEG_4X2[:200], "image/jpeg").glb()
    bad["uri-plus.gltf"] = raw_doc(textured, lambda d: d["images"][0].update(uri="leaf+1.png"))
    bad["uri-escape-malformed.gltf"] = raw_doc(textured, lambda d: d["images"][0].update(
        uri="leaf%2.png"))
    for name, uri in (("uri-parent", "../secret.bin"), ("uri-absolute", "/etc/passwd"),
                      ("uri-url", "http://example.invalid/a.bin"), ("uri-escape", "%2e%2e/x.bin"),
                      ("uri-device", "/dev/zero"), ("uri-local", "model.bin")):
        bad[name + ".gltf"] = raw_doc(t, lambda d: d["buffers"][0].update(uri=uri))
    deep = lambda n: "[" * n + "]" * n
    bad["extras-deep-300.gltf"] = raw_doc(t, lambda d: d.update(extras=json.loads(deep(300))))
    bad["extras-deep-20000.gltf"] = (b'{"asset":{"version":"2.0"},"extras":' +
                                     deep(20000).encode() + b"}")
    bad["not-json.gltf"] = b"{ this is not json"
    bad["bom-json.gltf"] = b"\xef\xbb\xbf" + t.gltf()
    seeds.update({"bad-" + k: v for k, v in bad.items()})
    return seeds


def scene_seeds():
    seeds = {}
    for f in sorted((ROOT / "data").rglob("*.json")):
        seeds["data-" + f.parent.name + "-" + f.name] = f.read_bytes()
    base = {
        "camera": {"eye": [0, 3, 4], "target": [0, 0, 0], "up": [0, 1, 0], "fov_y_deg": 45},
        "light": {"center": [0, 4, 0], "u": [0.5, 0, 0], "v": [0, 0, 0.5]},
        "objects": [{"type": "quad", "center": [0, 0, 0], "u": [4, 0, 0], "v": [0, 0, -4]}],
    }

    def scene(*objects, **top):
        d = json.loads(json.dumps(base))
        d["objects"] += list(objects)
        d.update(top)
        return json.dumps(d).encode()

    seeds["gltf-object.json"] = scene({"type": "gltf", "file": "triangle.gltf",
                                       "translate": [0, 1, 0], "rotate_deg": [0, 45, 0], "scale": 0.5})
    seeds["all-types.json"] = scene(
        {"type": "box", "center": [0, 1, 0], "size": [1, 1, 1], "rotate_deg": [10, 20, 30],
         "method": "wedges"},
        {"type": "sphere", "center": [1, 1, 0], "radius": 0.3, "segments": 8, "method": "occlusion"},
        {"type": "torus", "center": [-1, 1, 0], "major_radius": 0.5, "minor_radius": 0.1,
         "major_segments": 8, "minor_segments": 4, "name": "ring", "method": "none"})
    bad = {
        "sphere-segments-huge": scene({"type": "sphere", "center": [0, 1, 0], "radius": 1, "segments": 4096}),
        "sphere-segments-frac": scene({"type": "sphere", "center": [0, 1, 0], "radius": 1, "segments": 3.5}),
        "torus-horn": scene({"type": "torus", "center": [0, 1, 0], "major_radius": 1, "minor_radius": 1}),
        "box-negative": scene({"type": "box", "center": [0, 1, 0], "size": [1, -1, 1]}),
        "coordinate-huge": scene({"type": "box", "center": [1e8, 1, 0], "size": [1, 1, 1]}),
        "light-in-box": scene({"type": "box", "center": [0, 4, 0], "size": [2, 2, 2]}),
        "gltf-missing": scene({"type": "gltf", "file": "nothing-here.gltf"}),
        "gltf-device": scene({"type": "gltf", "file": "/dev/zero"}),
        "gltf-folder": scene({"type": "gltf", "file": "."}),
        "gltf-scale-zero": scene({"type": "gltf", "file": "triangle.gltf", "scale": [1, 0, 1]}),
        "unknown-key": scene(extra=1),
        "unknown-type": scene({"type": "cone"}),
    }
    text = {
        "number-1e999": b'{"camera": {"eye": [1e999, 0, 0], "target": [0, 0, 0]}}',
        "duplicate-key": b'{"camera": {}, "camera": {}}',
        "truncated": json.dumps(base).encode()[:90],
        "not-object": b"[1, 2, 3]",
        "empty": b"",
        "nul-bytes": b'{"camera"\0: 1}',
        "deep-65": b'{"camera": {"eye": ' + b"[" * 65 + b"]" * 65 + b"}}",
        "deep-5000": b'{"camera": {"eye": ' + b"[" * 5000 + b"]" * 5000 + b"}}",
        "deep-objects": b'{"a":' * 200 + b"1" + b"}" * 200,
        "bad-utf8": b'{"camera": "\xff\xfe"}',
        "escapes": b'{"camera": "\\ud800\\u0000"}',
    }
    seeds.update({"bad-" + k + ".json": v for k, v in bad.items()})
    seeds.update({"bad-" + k + ".json": v for k, v in text.items()})
    return seeds


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--kind", choices=("gltf", "scene_json", "all"), default="all")
    ap.add_argument("--out", required=True, type=pathlib.Path)
    ap.add_argument("--assets", type=pathlib.Path,
                    help="also write triangle.gltf, the model scene seeds name, into this folder")
    args = ap.parse_args()
    seeds = {}
    if args.kind in ("gltf", "all"):
        seeds.update({"gltf-" + k: v for k, v in gltf_seeds().items()})
    if args.kind in ("scene_json", "all"):
        seeds.update({"scene-" + k: v for k, v in scene_seeds().items()})
    args.out.mkdir(parents=True, exist_ok=True)
    for name, data in sorted(seeds.items()):
        (args.out / name).write_bytes(data)
    if args.assets:
        args.assets.mkdir(parents=True, exist_ok=True)
        (args.assets / "triangle.gltf").write_bytes(triangle().gltf())
    print("make-fuzz-corpus: %d seeds in %s" % (len(seeds), args.out))


if __name__ == "__main__":
    main()
