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


def textured(embed_in_view):
    b = triangle(5121)
    uv = b.accessor(b.view(struct.pack("<6H", 0, 0, 65535, 0, 0, 65535)), 5123, 3, "VEC2",
                    normalized=True)
    b.doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = uv
    b.doc["meshes"][0]["primitives"][0]["material"] = 0
    png = png_1x1([200, 100, 50, 128])
    if embed_in_view:
        b.doc["images"] = [{"bufferView": b.view(png), "mimeType": "image/png"}]
    else:
        b.doc["images"] = [{"uri": "data:image/png;base64," + base64.b64encode(png).decode()}]
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
        "lights_camera.glb": lights_and_camera().glb(),
        "sparse_strip_quantized.gltf": sparse_strip_quantized().gltf(),
    }
    for name, data in files.items():
        with open(os.path.join(OUT, name), "wb") as f:
            f.write(data)
        print(f"{name}: {len(data)} bytes")


if __name__ == "__main__":
    main()
