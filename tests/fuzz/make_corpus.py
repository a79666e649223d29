#!/usr/bin/env python3
"""Writes the fuzzer's seed corpus: tiny valid glTF/GLB files that between them reach every
feature the loader reads (indices of each type, strides, sparse accessors, strips, quantized
attributes, textures from data URIs and buffer views, lights, cameras, node hierarchies).

Run from anywhere: tests/fuzz/make_corpus.py (it writes tests/fuzz/corpus/)."""

import base64
import json
import os
import struct
import zlib

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus")

# A 2x2 baseline JPEG (red, green, blue, white), written once by stb_image_write at quality
# 50: Python's standard library has no JPEG encoder.
JPEG_2X2 = bytes.fromhex(
    "ffd8ffe000104a46494600010100000100010000ffdb008400100b0c0e0c0a100e0d0e1211101318281a1816"
    "16183123251d283a333d3c3933383740485c4e404457453738506d51575f626768673e4d71797064785c6567"
    "63011112121815182f1a1a2f6342384263636363636363636363636363636363636363636363636363636363"
    "63636363636363636363636363636363636363636363ffc00011080002000203012200021101031101ffc401"
    "a20000010501010101010100000000000000000102030405060708090a0b1000020103030204030505040400"
    "00017d01020300041105122131410613516107227114328191a1082342b1c11552d1f02433627282090a1617"
    "18191a25262728292a3435363738393a434445464748494a535455565758595a636465666768696a73747576"
    "7778797a838485868788898a92939495969798999aa2a3a4a5a6a7a8a9aab2b3b4b5b6b7b8b9bac2c3c4c5c6"
    "c7c8c9cad2d3d4d5d6d7d8d9dae1e2e3e4e5e6e7e8e9eaf1f2f3f4f5f6f7f8f9fa0100030101010101010101"
    "010000000000000102030405060708090a0b1100020102040403040705040400010277000102031104052131"
    "061241510761711322328108144291a1b1c109233352f0156272d10a162434e125f11718191a262728292a35"
    "363738393a434445464748494a535455565758595a636465666768696a737475767778797a82838485868788"
    "898a92939495969798999aa2a3a4a5a6a7a8a9aab2b3b4b5b6b7b8b9bac2c3c4c5c6c7c8c9cad2d3d4d5d6d7"
    "d8d9dae2e3e4e5e6e7e8e9eaf2f3f4f5f6f7f8f9faffda000c03010002110311003f00eb345b5b77d12c19e0"
    "8999ada324940493b455dfb1daff00cfb43ff7c0aafa1ffc8074effaf68fff0041157e9d58479e5a7523922f"
    "568fffd9")


def png_1x1(rgba):
    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    header = struct.pack(">IIBBBBB", 1, 1, 8, 6, 0, 0, 0)  # 1x1, 8-bit RGBA
    pixels = zlib.compress(b"\x00" + bytes(rgba))  # filter byte + one pixel
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", pixels) + chunk(b"IEND", b"")


class Builder:
    def __init__(self):
        self.doc = {"asset": {"version": "2.0"}}
        self.bin = bytearray()

    def view(self, data, stride=None):
        while len(self.bin) % 4:
            self.bin.append(0)
        view = {"buffer": 0, "byteOffset": len(self.bin), "byteLength": len(data)}
        if stride:
            view["byteStride"] = stride
        self.bin += data
        self.doc.setdefault("bufferViews", []).append(view)
        return len(self.doc["bufferViews"]) - 1

    def accessor(self, view, ctype, count, kind, **extra):
        acc = {"componentType": ctype, "count": count, "type": kind, **extra}
        if view is not None:
            acc["bufferView"] = view
        self.doc.setdefault("accessors", []).append(acc)
        return len(self.doc["accessors"]) - 1

    def positions(self, points):
        data = b"".join(struct.pack("<3f", *p) for p in points)
        return self.accessor(self.view(data), 5126, len(points), "VEC3")

    def gltf(self):
        doc = dict(self.doc)
        if self.bin:
            uri = "data:application/octet-stream;base64," + base64.b64encode(self.bin).decode()
            doc["buffers"] = [{"byteLength": len(self.bin), "uri": uri}]
        return json.dumps(doc, separators=(",", ":")).encode()

    def glb(self):
        doc = dict(self.doc)
        if self.bin:
            doc["buffers"] = [{"byteLength": len(self.bin)}]
        text = json.dumps(doc, separators=(",", ":")).encode()
        text += b" " * (-len(text) % 4)
        chunks = struct.pack("<II", len(text), 0x4E4F534A) + text
        if self.bin:
            data = bytes(self.bin) + b"\x00" * (-len(self.bin) % 4)
            chunks += struct.pack("<II", len(data), 0x004E4942) + data
        return struct.pack("<III", 0x46546C67, 2, 12 + len(chunks)) + chunks


def triangle(index_type=5123):
    b = Builder()
    pos = b.positions([(0, 0, 0), (1, 0, 0), (0, 1, 0)])
    fmt = {5121: "<3B", 5123: "<3H", 5125: "<3I"}[index_type]
    idx = b.accessor(b.view(struct.pack(fmt, 0, 1, 2)), index_type, 3, "SCALAR")
    b.doc["meshes"] = [{"primitives": [{"attributes": {"POSITION": pos}, "indices": idx}]}]
    b.doc["nodes"] = [{"mesh": 0}]
    b.doc["scenes"] = [{"nodes": [0]}]
    b.doc["scene"] = 0
    return b


def textured(embed_in_view, image=None):
    b = triangle(5121)
    uv = b.accessor(b.view(struct.pack("<6H", 0, 0, 65535, 0, 0, 65535)), 5123, 3, "VEC2",
                    normalized=True)
    b.doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = uv
    b.doc["meshes"][0]["primitives"][0]["material"] = 0
    data = image or png_1x1([200, 100, 50, 128])
    mime = "image/jpeg" if data[:2] == b"\xff\xd8" else "image/png"
    if embed_in_view:
        b.doc["images"] = [{"bufferView": b.view(data), "mimeType": mime}]
    else:
        b.doc["images"] = [{"uri": "data:%s;base64,%s" % (mime, base64.b64encode(data).decode())}]
    b.doc["samplers"] = [{}]
    b.doc["textures"] = [{"source": 0, "sampler": 0}]
    b.doc["materials"] = [{"name": "leaf", "alphaMode": "MASK", "alphaCutoff": 0.4,
                           "doubleSided": True,
                           "pbrMetallicRoughness": {"baseColorFactor": [1, 0.5, 0.5, 1],
                                                    "baseColorTexture": {"index": 0}},
                           "emissiveTexture": {"index": 0, "texCoord": 0}}]
    return b


def lights_and_camera():
    b = triangle(5125)
    b.doc["extensionsUsed"] = ["KHR_lights_punctual", "KHR_materials_emissive_strength",
                               "KHR_materials_transmission"]
    b.doc["extensions"] = {"KHR_lights_punctual": {"lights": [
        {"type": "point", "color": [1, 0.5, 0.2], "intensity": 20, "range": 5},
        {"type": "spot", "intensity": 50, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.6}},
        {"type": "directional", "intensity": 2}]}}
    b.doc["materials"] = [{"emissiveFactor": [1, 1, 1],
                           "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 5},
                                          "KHR_materials_transmission": {"transmissionFactor": 0.5}}}]
    b.doc["meshes"][0]["primitives"][0]["material"] = 0
    b.doc["cameras"] = [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.01}}]
    b.doc["nodes"] = [
        {"children": [1, 2], "translation": [1, 2, 3], "rotation": [0, 0.7071068, 0, 0.7071068]},
        {"mesh": 0, "scale": [2, 2, 2]},
        {"children": [3, 4, 5], "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 5, 0, 1]},
        {"extensions": {"KHR_lights_punctual": {"light": 0}}},
        {"extensions": {"KHR_lights_punctual": {"light": 1}}, "rotation": [-0.7071068, 0, 0, 0.7071068]},
        {"extensions": {"KHR_lights_punctual": {"light": 2}}, "camera": 0}]
    return b


def sparse_strip_quantized():
    b = Builder()
    b.doc["extensionsUsed"] = ["KHR_mesh_quantization"]
    # Interleaved: short positions (8 bytes with padding) in a stride-8 view.
    interleaved = b"".join(struct.pack("<4h", *p, 0) for p in [(0, 0, 0), (100, 0, 0), (0, 100, 0), (100, 100, 0)])
    pos = b.accessor(b.view(interleaved, stride=8), 5122, 4, "VEC3")
    normals = b.accessor(b.view(struct.pack("<16b", *([0, 0, 127, 0] * 4))), 5120, 4, "VEC3",
                         normalized=True)
    b.doc["bufferViews"][-1]["byteStride"] = 4
    sparse_idx = b.view(struct.pack("<2H", 1, 3))
    sparse_val = b.view(struct.pack("<6f", 0, 0, 1, 0, 0, 1))
    nonzero = b.accessor(None, 5126, 4, "VEC3", sparse={
        "count": 2, "indices": {"bufferView": sparse_idx, "componentType": 5123},
        "values": {"bufferView": sparse_val}})
    b.doc["meshes"] = [{"primitives": [
        {"attributes": {"POSITION": pos, "NORMAL": normals}, "mode": 5},
        {"attributes": {"POSITION": nonzero}, "mode": 6},
        {"attributes": {"POSITION": pos}, "mode": 1}]}]
    b.doc["nodes"] = [{"mesh": 0}]
    return b


def main():
    os.makedirs(OUT, exist_ok=True)
    files = {
        "triangle_u16.gltf": triangle(5123).gltf(),
        "triangle_u16.glb": triangle(5123).glb(),
        "textured_view.glb": textured(True).glb(),
        "textured_uri.gltf": textured(False).gltf(),
        "textured_jpeg.glb": textured(True, JPEG_2X2).glb(),
        "lights_camera.glb": lights_and_camera().glb(),
        "sparse_strip_quantized.gltf": sparse_strip_quantized().gltf(),
    }
    for name, data in files.items():
        with open(os.path.join(OUT, name), "wb") as f:
            f.write(data)
        print(f"{name}: {len(data)} bytes")


if __name__ == "__main__":
    main()
