#!/usr/bin/env python3
"""Checks the glTF scenes written by make_scenes.py (Python 3 standard library only).

    python3 scenes/tools/check_scenes.py [files...]
    (default: every scenes/*.gltf, then every scenes/*.ddgi.json sidecar)

Per file: the JSON parses, the data-URI buffers decode to their byteLength, every buffer view
and accessor lies in bounds and is aligned, every index is below the vertex count, the
POSITION min/max equal the data, every normal has unit length, every triangle's winding
(counter-clockwise front) agrees with its NORMAL attribute, every node/mesh/material/camera/
light has a name, extensionsUsed matches what is used, and the file is under 100 KB.
Per scene: each node's surface faces its intended side (into the room, out of a solid,
towards a point), closed surfaces are watertight with the expected orientation and volume,
and ray casts confirm the properties the tests rely on (the closed two-room shell lets
nothing through, the open door does, the furnace box is sealed, the cube shadows the floor).
Sidecars: only the keys of docs/sidecar-format.md, the scene and environment image exist,
every overridden material name exists in the glTF, and the scene ends up lit and with a
camera. Exit status 0 when every check passes.
"""

import base64
import glob
import json
import math
import os
import random
import struct
import sys

SCENES_DIR = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
MAX_BYTES = 100 * 1024

COMPONENTS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT4": 16}
FORMATS = {5120: "b", 5121: "B", 5122: "h", 5123: "H", 5125: "I", 5126: "f"}


class Failures:
    def __init__(self):
        self.items = []
        self.checks = 0

    def expect(self, ok, what):
        self.checks += 1
        if not ok:
            self.items.append(what)
        return ok


# ----------------------------------------------------------------------------- math

def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def scale(a, s):
    return (a[0] * s, a[1] * s, a[2] * s)


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def length(a):
    return math.sqrt(dot(a, a))


def normalize(a):
    n = length(a)
    return (a[0] / n, a[1] / n, a[2] / n)


def mat_mul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]


def trs_matrix(node):
    if "matrix" in node:
        m = node["matrix"]  # column-major
        return [[m[c * 4 + r] for c in range(4)] for r in range(4)]
    tx, ty, tz = node.get("translation", [0, 0, 0])
    qx, qy, qz, qw = node.get("rotation", [0, 0, 0, 1])
    sx, sy, sz = node.get("scale", [1, 1, 1])
    r = [[1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw)],
         [2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw)],
         [2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)]]
    return [[r[0][0] * sx, r[0][1] * sy, r[0][2] * sz, tx],
            [r[1][0] * sx, r[1][1] * sy, r[1][2] * sz, ty],
            [r[2][0] * sx, r[2][1] * sy, r[2][2] * sz, tz],
            [0, 0, 0, 1]]


def xform_point(m, p):
    return tuple(m[i][0] * p[0] + m[i][1] * p[1] + m[i][2] * p[2] + m[i][3] for i in range(3))


def xform_dir(m, d):
    return tuple(m[i][0] * d[0] + m[i][1] * d[1] + m[i][2] * d[2] for i in range(3))


def f32(x):
    return struct.unpack("<f", struct.pack("<f", x))[0]


# ----------------------------------------------------------------------------- file checks

def decode_buffers(doc, fail, base_dir):
    out = []
    for i, b in enumerate(doc.get("buffers", [])):
        uri = b.get("uri", "")
        data = b""
        if uri.startswith("data:"):
            head, _, payload = uri.partition(",")
            if fail.expect(head.endswith(";base64"), "buffers[%d]: data URI is not base64" % i):
                try:
                    data = base64.b64decode(payload, validate=True)
                except ValueError as e:
                    fail.expect(False, "buffers[%d]: base64 does not decode: %s" % (i, e))
        else:
            fail.expect(False, "buffers[%d]: not an embedded data URI: %r" % (i, uri[:40]))
            path = os.path.join(base_dir, uri)
            if os.path.exists(path):
                data = open(path, "rb").read()
        fail.expect(len(data) == b.get("byteLength"),
                    "buffers[%d]: %d bytes decoded, byteLength %s" % (i, len(data), b.get("byteLength")))
        out.append(data)
    return out


def read_accessor(doc, buffers, index, fail):
    acc = doc["accessors"][index]
    where = "accessors[%d]" % index
    ncomp = COMPONENTS[acc["type"]]
    fmt = FORMATS[acc["componentType"]]
    csize = struct.calcsize(fmt)
    elem = csize * ncomp
    view = doc["bufferViews"][acc["bufferView"]]
    buf = buffers[view["buffer"]]
    voff = view.get("byteOffset", 0)
    fail.expect(voff + view["byteLength"] <= len(buf), where + ": buffer view runs past the buffer")
    stride = view.get("byteStride", elem)
    aoff = acc.get("byteOffset", 0)
    count = acc["count"]
    fail.expect(count > 0, where + ": count 0")
    fail.expect((voff + aoff) % csize == 0, where + ": misaligned")
    fail.expect(aoff + stride * (count - 1) + elem <= view["byteLength"],
                where + ": runs past its buffer view")
    values = []
    for k in range(count):
        start = voff + aoff + k * stride
        if start + elem > len(buf):
            break
        v = struct.unpack_from("<%d%s" % (ncomp, fmt), buf, start)
        values.append(v if ncomp > 1 else v[0])
    if "min" in acc or "max" in acc:
        comps = [values] if ncomp == 1 else [[v[c] for v in values] for c in range(ncomp)]
        mins = [min(c) for c in comps]
        maxs = [max(c) for c in comps]
        fail.expect([f32(x) for x in acc.get("min", [])] == mins, where + ": min %s != data %s" % (acc.get("min"), mins))
        fail.expect([f32(x) for x in acc.get("max", [])] == maxs, where + ": max %s != data %s" % (acc.get("max"), maxs))
    return values


class Tri:
    __slots__ = ("a", "b", "c", "n", "node", "material")

    def __init__(self, a, b, c, node, material):
        self.a, self.b, self.c = a, b, c
        self.n = normalize(cross(sub(b, a), sub(c, a)))
        self.node, self.material = node, material

    def centroid(self):
        return scale(add(add(self.a, self.b), self.c), 1.0 / 3.0)


def check_file(path, fail):
    """Generic checks; returns (doc, world triangles, node world matrices)."""
    name = os.path.basename(path)
    size = os.path.getsize(path)
    fail.expect(size < MAX_BYTES, "%s: %d bytes, limit %d" % (name, size, MAX_BYTES))
    with open(path, encoding="utf-8") as f:
        doc = json.load(f)
    fail.expect(doc.get("asset", {}).get("version") == "2.0", "asset.version is not 2.0")
    buffers = decode_buffers(doc, fail, os.path.dirname(path))
    for kind in ("nodes", "meshes", "materials", "cameras"):
        for i, obj in enumerate(doc.get(kind, [])):
            fail.expect(bool(obj.get("name")), "%s[%d] has no name" % (kind, i))
    lights = doc.get("extensions", {}).get("KHR_lights_punctual", {}).get("lights", [])
    for i, light in enumerate(lights):
        fail.expect(bool(light.get("name")), "lights[%d] has no name" % i)
    used = set(doc.get("extensionsUsed", []))
    fail.expect(("KHR_lights_punctual" in used) == bool(lights),
                "KHR_lights_punctual in extensionsUsed must match the presence of lights")
    strength_used = False
    for i, m in enumerate(doc.get("materials", [])):
        ef = m.get("emissiveFactor", [0, 0, 0])
        fail.expect(all(0.0 <= c <= 1.0 for c in ef), "materials[%d]: emissiveFactor outside [0,1]" % i)
        bc = m.get("pbrMetallicRoughness", {}).get("baseColorFactor", [1, 1, 1, 1])
        fail.expect(all(0.0 <= c <= 1.0 for c in bc), "materials[%d]: baseColorFactor outside [0,1]" % i)
        strength_used |= "KHR_materials_emissive_strength" in m.get("extensions", {})
    fail.expect(("KHR_materials_emissive_strength" in used) == strength_used,
                "KHR_materials_emissive_strength in extensionsUsed must match its use")
    fail.expect(used <= {"KHR_lights_punctual", "KHR_materials_emissive_strength"},
                "unexpected extensions %s" % sorted(used))

    scene = doc["scenes"][doc.get("scene", 0)]
    world = {}

    def walk(i, parent):
        m = mat_mul(parent, trs_matrix(doc["nodes"][i]))
        world[i] = m
        for c in doc["nodes"][i].get("children", []):
            walk(c, m)

    ident = [[1 if r == c else 0 for c in range(4)] for r in range(4)]
    for i in scene["nodes"]:
        walk(i, ident)
    fail.expect(len(world) == len(doc["nodes"]), "some nodes are not in the default scene")

    tris = []
    for ni, m in world.items():
        node = doc["nodes"][ni]
        if "mesh" not in node:
            continue
        for pi, prim in enumerate(doc["meshes"][node["mesh"]]["primitives"]):
            where = "%s: node %s primitive %d" % (name, node.get("name"), pi)
            fail.expect(prim.get("mode", 4) == 4, where + ": not triangles")
            pos = read_accessor(doc, buffers, prim["attributes"]["POSITION"], fail)
            nrm = read_accessor(doc, buffers, prim["attributes"]["NORMAL"], fail)
            idx = read_accessor(doc, buffers, prim["indices"], fail)
            fail.expect(len(nrm) == len(pos), where + ": NORMAL count != POSITION count")
            fail.expect(len(idx) % 3 == 0, where + ": index count not a multiple of 3")
            fail.expect(all(0 <= k < len(pos) for k in idx), where + ": index out of range")
            bad = [k for k, n in enumerate(nrm) if abs(length(n) - 1.0) > 1e-6]
            fail.expect(not bad, where + ": %d normals not unit length" % len(bad))
            mat = doc["materials"][prim["material"]]["name"]
            for t in range(0, len(idx) - 2, 3):
                i0, i1, i2 = idx[t:t + 3]
                if max(i0, i1, i2) >= len(pos):
                    continue
                a, b, c = (xform_point(m, pos[k]) for k in (i0, i1, i2))
                area2 = length(cross(sub(b, a), sub(c, a)))
                if not fail.expect(area2 > 1e-9, where + ": degenerate triangle %d" % (t // 3)):
                    continue
                tri = Tri(a, b, c, node.get("name"), mat)
                agree = all(dot(normalize(xform_dir(m, nrm[k])), tri.n) > 0.999  # rigid transforms
                            for k in (i0, i1, i2))
                fail.expect(agree, where + ": triangle %d winding disagrees with NORMAL" % (t // 3))
                tris.append(tri)
    cams = [i for i in world if "camera" in doc["nodes"][i]]
    fail.expect(len(cams) >= 1, name + ": no camera node")
    for ci in cams:
        cam = doc["cameras"][doc["nodes"][ci]["camera"]]
        fail.expect(cam.get("type") == "perspective", name + ": camera is not perspective")
    return doc, tris, world


# ----------------------------------------------------------------------------- geometry checks

def node_tris(tris, node):
    return [t for t in tris if t.node == node]


def signed_volume(ts):
    return sum(dot(t.a, cross(t.b, t.c)) for t in ts) / 6.0


def is_watertight(ts):
    """Every directed edge is matched by exactly one reverse edge (positions to 1e-6 m)."""
    def key(p):
        return tuple(round(v * 1e6) for v in p)

    edges = {}
    for t in ts:
        for p, q in ((t.a, t.b), (t.b, t.c), (t.c, t.a)):
            e = (key(p), key(q))
            edges[e] = edges.get(e, 0) + 1
    return all(n == 1 and edges.get((e[1], e[0]), 0) == 1 for e, n in edges.items())


def bbox(ts):
    pts = [p for t in ts for p in (t.a, t.b, t.c)]
    return ([min(p[a] for p in pts) for a in range(3)], [max(p[a] for p in pts) for a in range(3)])


def close(a, b, eps=1e-5):
    return all(abs(x - y) <= eps for x, y in zip(a, b))


def faces_toward(ts, point):
    return all(dot(t.n, sub(point, t.centroid())) > 0.0 for t in ts)


def faces_away(ts, point):
    return all(dot(t.n, sub(t.centroid(), point)) > 0.0 for t in ts)


def check_solid(fail, ts, name, outward=True, volume=None):
    fail.expect(len(ts) > 0, name + ": missing")
    if not ts:
        return
    fail.expect(is_watertight(ts), name + ": not a closed surface")
    v = signed_volume(ts)
    fail.expect(v > 0 if outward else v < 0,
                name + ": faces point %s (signed volume %.4f)" % ("in" if outward else "out", v))
    if volume is not None:
        fail.expect(abs(abs(v) - volume) < 1e-5, name + ": volume %.5f, expected %.5f" % (abs(v), volume))


def intersect(tris, origin, d, tmin=1e-6):
    """Nearest hit (t, tri) of a ray, or None (Moller-Trumbore, both faces)."""
    best = None
    for tri in tris:
        e1, e2 = sub(tri.b, tri.a), sub(tri.c, tri.a)
        p = cross(d, e2)
        det = dot(e1, p)
        if abs(det) < 1e-12:
            continue
        inv = 1.0 / det
        s = sub(origin, tri.a)
        u = dot(s, p) * inv
        if u < 0.0 or u > 1.0:
            continue
        q = cross(s, e1)
        v = dot(d, q) * inv
        if v < 0.0 or u + v > 1.0:
            continue
        t = dot(e2, q) * inv
        if t > tmin and (best is None or t < best[0]):
            best = (t, tri)
    return best


def random_dir(rng):
    while True:
        d = (rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1))
        n = length(d)
        if 1e-3 < n <= 1.0:
            return scale(d, 1.0 / n)


def node_pos(doc, world, name):
    for i, m in world.items():
        if doc["nodes"][i].get("name") == name:
            return (m[0][3], m[1][3], m[2][3])
    return None


def camera_ray(doc, world):
    for i, m in world.items():
        if "camera" in doc["nodes"][i]:
            return (m[0][3], m[1][3], m[2][3]), normalize(xform_dir(m, (0, 0, -1)))
    return None


def light_of(doc, world, name):
    lights = doc.get("extensions", {}).get("KHR_lights_punctual", {}).get("lights", [])
    for i, m in world.items():
        n = doc["nodes"][i]
        if n.get("name") == name and "KHR_lights_punctual" in n.get("extensions", {}):
            return lights[n["extensions"]["KHR_lights_punctual"]["light"]], (m[0][3], m[1][3], m[2][3])
    return None, None


def check_camera_sees_front(fail, doc, world, tris, name):
    eye, fwd = camera_ray(doc, world)
    hit = intersect(tris, eye, fwd)
    if fail.expect(hit is not None, name + ": the camera's centre ray hits nothing"):
        fail.expect(dot(hit[1].n, fwd) < 0.0, name + ": the camera's centre ray hits a back face")
    return hit


def check_cornell(fail, doc, tris, world):
    n = "cornell_box"
    centre = (0.0, 1.0, 0.0)
    for wall, normal in (("floor", (0, 1, 0)), ("ceiling", (0, -1, 0)), ("back_wall", (0, 0, 1)),
                         ("left_wall_red", (1, 0, 0)), ("right_wall_green", (-1, 0, 0))):
        ts = node_tris(tris, wall)
        fail.expect(len(ts) == 2, "%s: %s has %d triangles" % (n, wall, len(ts)))
        fail.expect(all(close(t.n, normal) for t in ts), "%s: %s does not face %s" % (n, wall, normal))
        fail.expect(faces_toward(ts, centre), "%s: %s does not face into the box" % (n, wall))
    lo, hi = bbox([t for t in tris if t.node in ("floor", "ceiling", "back_wall", "left_wall_red",
                                                  "right_wall_green")])
    fail.expect(close(lo, (-1, 0, -1)) and close(hi, (1, 2, 1)), n + ": interior bounds %s %s" % (lo, hi))
    for b, h in (("short_box", 0.6), ("tall_box", 1.2)):
        ts = node_tris(tris, b)
        check_solid(fail, ts, n + ": " + b, True, 0.36 * h)
        blo, bhi = bbox(ts)
        fail.expect(abs(blo[1]) < 1e-6 and abs(bhi[1] - h) < 1e-6, n + ": %s height" % b)
        fail.expect(all(-1 < blo[a] and bhi[a] < 1 for a in (0, 2)), n + ": %s outside the room" % b)
    mats = {t.material for t in tris}
    fail.expect({t.material for t in node_tris(tris, "left_wall_red")} == {"cornell_red"}, n + ": left wall not red")
    fail.expect({t.material for t in node_tris(tris, "right_wall_green")} == {"cornell_green"}, n + ": right wall not green")
    fail.expect(mats == {"cornell_white", "cornell_red", "cornell_green"}, n + ": materials %s" % mats)
    light, lp = light_of(doc, world, "ceiling_light")
    fail.expect(light is not None and light["type"] == "point" and 2.0 <= light["intensity"] <= 5.0,
                n + ": expected one point light of 2-5 W/sr")
    fail.expect(len(doc["extensions"]["KHR_lights_punctual"]["lights"]) == 1, n + ": more than one light")
    fail.expect(lp is not None and abs(lp[1] - 1.9) < 1e-6, n + ": light not at y = 1.9")
    fail.expect(not any("emissiveFactor" in m for m in doc["materials"]), n + ": emissive material present")
    hit = check_camera_sees_front(fail, doc, world, tris, n)
    eye, fwd = camera_ray(doc, world)
    fail.expect(eye[2] > 3.0, n + ": camera not in front of the open side")
    fail.expect(hit is not None and hit[1].node in ("back_wall", "tall_box", "short_box"),
                n + ": camera does not look into the box")


def check_two_room_shell(fail, doc, tris, n):
    """The shell both two-room scenes share: a closed box facing into the rooms. Returns its
    bounds."""
    ex = doc["asset"]["extras"]
    smin, smax = ex["shell"]["min"], ex["shell"]["max"]
    shell = node_tris(tris, "rooms_shell")
    check_solid(fail, shell, n + ": rooms_shell", outward=False,
                volume=(smax[0] - smin[0]) * (smax[1] - smin[1]) * (smax[2] - smin[2]))
    centre = scale(add(tuple(smin), tuple(smax)), 0.5)
    fail.expect(faces_toward(shell, centre), n + ": rooms_shell faces must point into the rooms")
    lo, hi = bbox(shell)
    fail.expect(close(lo, smin) and close(hi, smax), n + ": shell bounds")
    fail.expect(3.5 <= -smin[0] <= 4.5 and 3.5 <= smax[0] <= 4.5 and abs(smax[1] - 3) < 1e-9
                and abs(smax[2] - smin[2] - 4) < 1e-9, n + ": rooms are not about 4 x 3 x 4 m")
    return smin, smax


def check_two_rooms(fail, doc, tris, world, open_door):
    n = "two_rooms_" + ("open" if open_door else "closed")
    smin, smax = check_two_room_shell(fail, doc, tris, n)
    wall = node_tris(tris, "shared_wall")
    t = 0.02
    check_solid(fail, wall, n + ": shared_wall", True,
                volume=t * ((smax[1] - smin[1]) * (smax[2] - smin[2]) - 0.9 * 2.0))
    wlo, whi = bbox(wall)
    fail.expect(close(wlo, (-t / 2, smin[1], smin[2])) and close(whi, (t / 2, smax[1], smax[2])),
                n + ": shared wall bounds %s %s" % (wlo, whi))
    fail.expect(any(close(tr.n, (-1, 0, 0)) for tr in wall) and any(close(tr.n, (1, 0, 0)) for tr in wall),
                n + ": the shared wall must have front faces towards both rooms")
    # No probe plane of a grid fitted to the shell with spacing 1, 0.5 or 0.25 m falls in the wall.
    for spacing in (1.0, 0.5, 0.25):
        k = (0.0 - smin[0]) / spacing
        fail.expect(abs(k - round(k)) * spacing > t, n + ": probe plane inside the wall at spacing %g" % spacing)
    door = node_tris(tris, "door")
    check_solid(fail, door, n + ": door", True, volume=t * 0.9 * 2.0)
    dlo, dhi = bbox(door)
    if open_door:
        fail.expect(close(dlo, (t / 2, 0, -0.45)) and close(dhi, (t / 2 + 0.9, 2, -0.45 + t)),
                    n + ": open door bounds %s %s" % (dlo, dhi))
    else:
        fail.expect(close(dlo, (-t / 2, 0, -0.45)) and close(dhi, (t / 2, 2, 0.45)),
                    n + ": closed door must fill the doorway exactly: %s %s" % (dlo, dhi))
    light, lp = light_of(doc, world, "lit_room_light")
    fail.expect(light is not None and light["type"] == "point", n + ": no point light in the lit room")
    fail.expect(lp is not None and smin[0] < lp[0] < -t, n + ": the light is not in the lit room")
    eye, fwd = camera_ray(doc, world)
    fail.expect(t / 2 < eye[0] < smax[0] and smin[1] < eye[1] < smax[1] and smin[2] < eye[2] < smax[2],
                n + ": camera not in the dark room")
    fail.expect(fwd[0] < 0.0, n + ": camera does not look towards the shared wall")
    hit = check_camera_sees_front(fail, doc, world, tris, n)
    # Ray casts from the light: nothing escapes the shell; the dark room is reached only
    # when the door is open.
    rng = random.Random(1)
    escaped, dark_hits, back_hits = 0, 0, 0
    for _ in range(3000):
        d = random_dir(rng)
        h = intersect(tris, lp, d)
        if h is None:
            escaped += 1
            continue
        if dot(h[1].n, d) >= 0.0:
            back_hits += 1
        p = add(lp, scale(d, h[0]))
        if p[0] > t / 2 + 1e-6:
            dark_hits += 1
    fail.expect(escaped == 0, n + ": %d rays from the light escaped the shell" % escaped)
    fail.expect(back_hits == 0, n + ": %d rays from the light hit a back face" % back_hits)
    if open_door:
        fail.expect(dark_hits > 0, n + ": no direct light reaches the dark room through the door")
    else:
        fail.expect(dark_hits == 0, n + ": %d light rays reach the dark room with the door closed" % dark_hits)
    # From points spread over the dark room: with the door closed no ray reaches the lit room.
    reach_lit = 0
    for _ in range(3000):
        o = (rng.uniform(t / 2 + 0.05, smax[0] - 0.05), rng.uniform(0.05, smax[1] - 0.05),
             rng.uniform(smin[2] + 0.05, smax[2] - 0.05))
        d = random_dir(rng)
        h = intersect(tris, o, d)
        if h is None:
            escaped += 1
            continue
        if add(o, scale(d, h[0]))[0] < -t / 2 - 1e-6:
            reach_lit += 1
    fail.expect(escaped == 0, n + ": rays from the dark room escaped the shell")
    if open_door:
        fail.expect(reach_lit > 0, n + ": the open doorway does not connect the rooms")
    else:
        fail.expect(reach_lit == 0, n + ": %d rays pass from the dark room into the lit room" % reach_lit)


def check_two_rooms_plane_wall(fail, doc, tris, world):
    n = "two_rooms_plane_wall"
    smin, smax = check_two_room_shell(fail, doc, tris, n)
    wall = node_tris(tris, "plane_wall")
    fail.expect(len(wall) == 2 and all(close(t.n, (-1, 0, 0)) for t in wall),
                n + ": plane_wall must be one quad facing the lit room")
    if wall:
        wlo, whi = bbox(wall)
        fail.expect(close(wlo, (0, smin[1], smin[2])) and close(whi, (0, smax[1], smax[2])),
                    n + ": the plane wall must fill the section x = 0: %s %s" % (wlo, whi))
    wall_mats = {t.material for t in wall}
    fail.expect(all(m.get("doubleSided") is True for m in doc["materials"] if m["name"] in wall_mats),
                n + ": the plane wall's material must be double-sided")
    fail.expect(all(m.get("doubleSided") is not True for m in doc["materials"]
                    if m["name"] not in wall_mats), n + ": only the plane wall is double-sided")
    light, lp = light_of(doc, world, "lit_room_light")
    fail.expect(light is not None and light["type"] == "point" and lp is not None and
                smin[0] < lp[0] < 0.0, n + ": no point light in the lit room")
    eye, fwd = camera_ray(doc, world)
    fail.expect(0.0 < eye[0] < smax[0] and fwd[0] < 0.0,
                n + ": camera not in the dark room looking at the wall")
    # The wall is the only thing between the rooms: no ray from the light reaches x > 0 and
    # no ray from the dark room reaches x < 0.
    rng = random.Random(1)
    crossed, escaped = 0, 0
    for _ in range(3000):
        for origin, side in ((lp, -1.0), ((rng.uniform(0.05, smax[0] - 0.05), rng.uniform(0.05, smax[1] - 0.05),
                                            rng.uniform(smin[2] + 0.05, smax[2] - 0.05)), 1.0)):
            if origin is None:
                continue
            d = random_dir(rng)
            h = intersect(tris, origin, d)
            if h is None:
                escaped += 1
            elif add(origin, scale(d, h[0]))[0] * side < -1e-6:
                crossed += 1
    fail.expect(escaped == 0, n + ": %d rays escaped the shell" % escaped)
    fail.expect(crossed == 0, n + ": %d rays pass between the rooms" % crossed)

def check_white_box(fail, doc, tris, world):
    n = "white_box"
    ts = node_tris(tris, "furnace_box")
    check_solid(fail, ts, n + ": furnace_box", outward=False, volume=8.0)
    lo, hi = bbox(ts)
    fail.expect(close(lo, (-1, 0, -1)) and close(hi, (1, 2, 1)), n + ": interior bounds")
    fail.expect(faces_toward(ts, (0, 1, 0)), n + ": faces must point into the box")
    fail.expect(len(doc["materials"]) == 1, n + ": expected one material")
    m = doc["materials"][0]
    fail.expect(m.get("emissiveFactor") == [1.0, 1.0, 1.0], n + ": emissive must be (1,1,1)")
    fail.expect(m["pbrMetallicRoughness"]["baseColorFactor"][:3] == [0.5, 0.5, 0.5], n + ": albedo must be 0.5")
    fail.expect(m["pbrMetallicRoughness"].get("metallicFactor") == 0.0, n + ": must be dielectric")
    fail.expect("KHR_lights_punctual" not in doc.get("extensions", {}), n + ": must have no lights")
    eye, _ = camera_ray(doc, world)
    fail.expect(all(lo[a] < eye[a] < hi[a] for a in range(3)), n + ": camera not inside the box")
    check_camera_sees_front(fail, doc, world, tris, n)
    rng = random.Random(2)
    bad = 0
    for _ in range(2000):
        d = random_dir(rng)
        h = intersect(tris, eye, d)
        if h is None or dot(h[1].n, d) >= 0.0:
            bad += 1
    fail.expect(bad == 0, n + ": %d rays from the camera escape or hit a back face" % bad)


def check_box_on_floor(fail, doc, tris, world):
    n = "box_on_floor"
    floor = node_tris(tris, "floor")
    fail.expect(all(close(t.n, (0, 1, 0)) for t in floor) and len(floor) == 2, n + ": floor must face up")
    lo, hi = bbox(floor)
    fail.expect(close(lo, (-4, 0, -4)) and close(hi, (4, 0, 4)), n + ": floor must be 8 x 8 m at y = 0")
    fail.expect(doc["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"][:3] == [0.8, 0.8, 0.8],
                n + ": floor albedo must be 0.8")
    occ = node_tris(tris, "occluder")
    check_solid(fail, occ, n + ": occluder", True, 1.0)
    olo, ohi = bbox(occ)
    fail.expect(abs(olo[1]) < 1e-9 and abs(ohi[1] - 1) < 1e-9, n + ": occluder must stand on the floor")
    light, lp = light_of(doc, world, "key_light")
    fail.expect(light is not None and light["type"] == "point", n + ": no point light")

    def lit(p):
        d = sub(lp, p)
        dist = length(d)
        h = intersect(tris, add(p, (0, 1e-4, 0)), scale(d, 1.0 / dist))
        return h is None or h[0] > dist

    fail.expect(not lit((1.2, 0.0, 0.0)) and not lit((1.8, 0.0, 0.8)), n + ": shadow points are lit")
    fail.expect(lit((1.2, 0.0, 1.5)) and lit((1.9, 0.0, 0.0)) and lit((-1.5, 0.0, 0.0)),
                n + ": points outside the shadow are dark")
    hit = check_camera_sees_front(fail, doc, world, tris, n)
    eye, fwd = camera_ray(doc, world)
    if hit:
        p = add(eye, scale(fwd, hit[0]))
        fail.expect(hit[1].node == "floor" and 0.5 <= p[0] <= 11.0 / 6.0 and abs(p[2]) < 5.0 / 6.0,
                    n + ": the camera's centre ray does not land in the shadow (%s)" % (p,))


# ----------------------------------------------------------------------------- sidecars

SIDECAR_KEYS = {"scene", "camera", "environment", "lights", "materials", "probe_grid"}
MATERIAL_KEYS = {"base_color", "emissive", "emissive_strength", "transmission", "double_sided"}


def load_gltf_json(path):
    if path.endswith(".glb"):
        with open(path, "rb") as f:
            data = f.read()
        magic, version, _ = struct.unpack_from("<4sII", data, 0)
        chunk_len, chunk_type = struct.unpack_from("<I4s", data, 12)
        if magic != b"glTF" or version != 2 or chunk_type != b"JSON":
            raise ValueError("not a glTF 2.0 binary")
        return json.loads(data[20:20 + chunk_len])
    with open(path, encoding="utf-8") as f:
        return json.load(f)


def finite_vec(v, n):
    return isinstance(v, list) and len(v) == n and all(
        isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x) for x in v)


def check_sidecar(path, fail):
    """The keys and values of docs/sidecar-format.md, the files it names, and that the scene
    ends up with a camera and a light."""
    name = os.path.basename(path)
    base = os.path.dirname(path)
    with open(path, encoding="utf-8") as f:
        sc = json.load(f)
    fail.expect(set(sc) <= SIDECAR_KEYS, "%s: unknown keys %s" % (name, sorted(set(sc) - SIDECAR_KEYS)))
    scene_path = os.path.normpath(os.path.join(base, sc.get("scene", "")))
    if not fail.expect(os.path.isfile(scene_path) and scene_path.endswith((".gltf", ".glb")),
                       "%s: scene %r does not exist" % (name, sc.get("scene"))):
        return
    # A real scene by others (never copied here), or one of the generated scenes beside it.
    generated = "/" not in sc["scene"]
    fail.expect(sc["scene"].startswith("../../shared/scenes/") or generated,
                "%s: scene must be referenced as ../../shared/scenes/... or be a generated scene "
                "in scenes/" % name)
    doc = load_gltf_json(scene_path)
    mat_names = {m.get("name") for m in doc.get("materials", [])}
    cam = sc.get("camera")
    if cam is not None:
        fail.expect(set(cam) <= {"position", "target", "up", "yfov_degrees"}, name + ": camera keys")
        pos, tgt, up = cam.get("position"), cam.get("target"), cam.get("up", [0, 1, 0])
        if fail.expect(finite_vec(pos, 3) and finite_vec(tgt, 3) and finite_vec(up, 3),
                       name + ": camera vectors"):
            fwd = sub(tuple(tgt), tuple(pos))
            fail.expect(length(fwd) > 0 and length(cross(normalize(fwd), tuple(up))) > 1e-3,
                        name + ": camera position == target or up parallel to the view")
        fail.expect(0 < cam.get("yfov_degrees", 40) <= 179, name + ": yfov_degrees")
    env = sc.get("environment")
    if env is not None:
        fail.expect(set(env) <= {"color", "image", "intensity", "rotation_degrees"}, name + ": environment keys")
        if "image" in env:
            img = os.path.normpath(os.path.join(base, env["image"]))
            fail.expect(os.path.isfile(img) and img.endswith(".exr"), "%s: environment image %r missing" % (name, env["image"]))
        fail.expect(env.get("intensity", 1) >= 0, name + ": environment intensity")
    for mname, over in sc.get("materials", {}).items():
        fail.expect(mname in mat_names, "%s: material %r is not in %s" % (name, mname, os.path.basename(scene_path)))
        fail.expect(set(over) <= MATERIAL_KEYS, "%s: materials.%s keys %s" % (name, mname, sorted(over)))
        if "emissive" in over:
            fail.expect(finite_vec(over["emissive"], 3) and min(over["emissive"]) >= 0, name + ": emissive")
        fail.expect(over.get("emissive_strength", 0) >= 0, name + ": emissive_strength")
    # Real scenes are measured with their own lights; a generated scene's sidecar may add the
    # lights glTF cannot hold well (a sun).
    fail.expect(generated or not sc.get("lights"), name + ": unexpected extra lights")
    for light in sc.get("lights", []):
        fail.expect(light.get("type") in ("point", "spot", "directional"), name + ": light type")
        if light.get("type") == "directional":
            d = light.get("direction")
            fail.expect(finite_vec(d, 3) and length(tuple(d)) > 0, name + ": light direction")
        fail.expect(light.get("intensity", 1) >= 0, name + ": light intensity")
    # The scene must render lit and from some view.
    used_mats = {p.get("material") for n in doc.get("nodes", []) if "mesh" in n
                 for p in doc["meshes"][n["mesh"]]["primitives"]}
    emissive = [doc["materials"][i].get("name") for i in used_mats if i is not None and
                max(doc["materials"][i].get("emissiveFactor", [0, 0, 0])) > 0]
    emissive += [m for m, o in sc.get("materials", {}).items()
                 if max(o.get("emissive", [0])) > 0 and o.get("emissive_strength", 1) > 0]
    punctual = doc.get("extensions", {}).get("KHR_lights_punctual", {}).get("lights", [])
    fail.expect(bool(emissive or punctual or sc.get("lights") or env), name + ": the scene has no light")
    fail.expect(bool(doc.get("cameras")) or cam is not None, name + ": the scene has no camera")
    print("ok  " if not fail.items else "FAIL", "%-26s -> %s: %d punctual lights, emissive %s, %s camera%s" % (
        name, os.path.relpath(scene_path, base), len(punctual), sorted(set(emissive)) or "none",
        "sidecar" if cam is not None else "glTF",
        ", environment" if env else ""))


SCENE_CHECKS = {
    "cornell_box.gltf": check_cornell,
    "two_rooms_closed.gltf": lambda f, d, t, w: check_two_rooms(f, d, t, w, False),
    "two_rooms_open.gltf": lambda f, d, t, w: check_two_rooms(f, d, t, w, True),
    "two_rooms_plane_wall.gltf": check_two_rooms_plane_wall,
    "white_box.gltf": check_white_box,
    "box_on_floor.gltf": check_box_on_floor,
}


def main(argv):
    files = argv[1:] or sorted(glob.glob(os.path.join(SCENES_DIR, "*.gltf")))
    missing = [k for k in SCENE_CHECKS if not argv[1:] and
               not os.path.exists(os.path.join(SCENES_DIR, k))]
    failed = bool(missing)
    for name in missing:
        print("MISSING %s" % name)
    for path in files:
        fail = Failures()
        tris = []
        try:
            doc, tris, world = check_file(path, fail)
            scene_check = SCENE_CHECKS.get(os.path.basename(path))
            if scene_check:
                scene_check(fail, doc, tris, world)
            else:
                fail.expect(False, "no scene-specific checks for this file")
        except Exception as e:  # report and go on with the next file
            fail.expect(False, "exception: %r" % (e,))
        status = "ok  " if not fail.items else "FAIL"
        print("%s %-22s %4d checks, %d triangles" % (status, os.path.basename(path), fail.checks,
                                                      len(tris)))
        for item in fail.items:
            print("     " + item)
        failed |= bool(fail.items)
    if not argv[1:]:
        for path in sorted(glob.glob(os.path.join(SCENES_DIR, "*.ddgi.json"))):
            fail = Failures()
            try:
                check_sidecar(path, fail)
            except Exception as e:
                fail.expect(False, "exception: %r" % (e,))
                print("FAIL", os.path.basename(path))
            for item in fail.items:
                print("     " + item)
            failed |= bool(fail.items)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
