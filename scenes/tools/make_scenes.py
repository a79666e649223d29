#!/usr/bin/env python3
"""Writes the repo's small glTF 2.0 test scenes into scenes/.

Python 3 standard library only. Run from anywhere:

    python3 scenes/tools/make_scenes.py

The outputs are committed (CI does not run Python); rerun this script after changing it and
commit both. The output is deterministic. scenes/tools/check_scenes.py validates the files.

Conventions: metres, +Y up, right-handed, glTF's counter-clockwise front faces. Every face
carries its own four vertices with a flat normal (no smoothing across edges). A closed room
is a set of single-sided quads facing into the room; a solid object (box, thin wall, door) is
a closed surface facing out, so both sides of a thin wall are front faces. Light units are
radiometric: point-light intensity in W/sr, emissive factor in W/(m^2 sr) radiance.
"""

import base64
import json
import math
import os
import struct

GENERATOR = "ddgi scenes/tools/make_scenes.py"
OUT_DIR = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

FLOAT = 5126
UNSIGNED_SHORT = 5123
ARRAY_BUFFER = 34962
ELEMENT_ARRAY_BUFFER = 34963


# ----------------------------------------------------------------------------- vector helpers

def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def normalize(a):
    n = math.sqrt(dot(a, a))
    return (a[0] / n, a[1] / n, a[2] / n)


def f32(x):
    """The value as stored in a float32 buffer (so that JSON min/max equal the data)."""
    return struct.unpack("<f", struct.pack("<f", x))[0]


def quat_y(degrees):
    """Rotation about +Y as a glTF quaternion [x, y, z, w]."""
    h = math.radians(degrees) / 2.0
    return [0.0, math.sin(h), 0.0, math.cos(h)]


def quat_from_basis(x_axis, y_axis, z_axis):
    """Unit quaternion [x, y, z, w] of the rotation whose matrix columns are the given axes."""
    m00, m10, m20 = x_axis
    m01, m11, m21 = y_axis
    m02, m12, m22 = z_axis
    trace = m00 + m11 + m22
    if trace > 0.0:
        s = math.sqrt(trace + 1.0) * 2.0
        q = [(m21 - m12) / s, (m02 - m20) / s, (m10 - m01) / s, 0.25 * s]
    elif m00 > m11 and m00 > m22:
        s = math.sqrt(1.0 + m00 - m11 - m22) * 2.0
        q = [0.25 * s, (m01 + m10) / s, (m02 + m20) / s, (m21 - m12) / s]
    elif m11 > m22:
        s = math.sqrt(1.0 + m11 - m00 - m22) * 2.0
        q = [(m01 + m10) / s, 0.25 * s, (m12 + m21) / s, (m02 - m20) / s]
    else:
        s = math.sqrt(1.0 + m22 - m00 - m11) * 2.0
        q = [(m02 + m20) / s, (m12 + m21) / s, 0.25 * s, (m10 - m01) / s]
    n = math.sqrt(sum(c * c for c in q))
    q = [c / n for c in q]
    if q[3] < 0.0:
        q = [-c for c in q]
    return q


def look_at_rotation(eye, target, up=(0.0, 1.0, 0.0)):
    """glTF camera rotation: the camera looks along its local -Z with local +Y up."""
    forward = normalize(sub(target, eye))
    right = normalize(cross(forward, up))
    true_up = cross(right, forward)
    back = (-forward[0], -forward[1], -forward[2])
    return quat_from_basis(right, true_up, back)


# ----------------------------------------------------------------------------- geometry

class MeshData:
    """Triangles of one primitive: per-face vertices, flat normals, 16-bit indices."""

    def __init__(self):
        self.positions = []
        self.normals = []
        self.indices = []

    def quad(self, corners, normal):
        """Adds a planar quad. `corners` go around the quad in either order; the triangles are
        wound counter-clockwise as seen from the side `normal` points to."""
        normal = normalize(normal)
        face = cross(sub(corners[1], corners[0]), sub(corners[2], corners[0]))
        if dot(face, normal) < 0.0:
            corners = [corners[0], corners[3], corners[2], corners[1]]
        base = len(self.positions)
        for c in corners:
            self.positions.append(tuple(float(v) for v in c))
            self.normals.append(normal)
        self.indices += [base, base + 1, base + 2, base, base + 2, base + 3]

    def rect(self, axis, value, lo, hi, sign):
        """Axis-aligned rectangle in the plane coordinate[axis] = value, spanning the other two
        axes from lo to hi (3-vectors; the entry at `axis` is ignored), facing sign * e_axis."""
        u, v = [a for a in range(3) if a != axis]
        corners = []
        for cu, cv in ((lo[u], lo[v]), (hi[u], lo[v]), (hi[u], hi[v]), (lo[u], hi[v])):
            p = [0.0, 0.0, 0.0]
            p[axis] = value
            p[u] = cu
            p[v] = cv
            corners.append(tuple(p))
        n = [0.0, 0.0, 0.0]
        n[axis] = float(sign)
        self.quad(corners, tuple(n))

    def triangle_count(self):
        return len(self.indices) // 3


def cell_faces(grid, filled, inward=False, material_of=None):
    """Boundary of a union of cells of an axis-aligned grid.

    grid: three sorted lists of coordinates (cell edges along x, y, z).
    filled(i, j, k): whether cell (i, j, k) belongs to the region.
    Emits one quad per cell face that separates a filled cell from an empty one (or from the
    outside of the grid). Faces face out of the region, or into it when `inward` (a room seen
    from inside). Because every quad is one face of one grid cell, neighbouring quads share
    their corner vertices exactly: the surface is closed and has no T-junctions.
    material_of(i, j, k) groups the faces by key (default: one group); returns {key: MeshData}.
    """
    counts = [len(g) - 1 for g in grid]
    groups = {}

    def is_filled(c):
        if any(c[a] < 0 or c[a] >= counts[a] for a in range(3)):
            return False
        return filled(*c)

    for i in range(counts[0]):
        for j in range(counts[1]):
            for k in range(counts[2]):
                cell = (i, j, k)
                if not filled(*cell):
                    continue
                lo = (grid[0][i], grid[1][j], grid[2][k])
                hi = (grid[0][i + 1], grid[1][j + 1], grid[2][k + 1])
                key = material_of(*cell) if material_of else None
                for axis in range(3):
                    for side in (-1, 1):
                        nb = list(cell)
                        nb[axis] += side
                        if is_filled(tuple(nb)):
                            continue
                        value = hi[axis] if side > 0 else lo[axis]
                        mesh = groups.setdefault(key, MeshData())
                        mesh.rect(axis, value, lo, hi, -side if inward else side)
    return groups


def box(lo, hi, inward=False):
    """A closed axis-aligned box from corner lo to corner hi."""
    grid = [[lo[a], hi[a]] for a in range(3)]
    return cell_faces(grid, lambda i, j, k: True, inward)[None]


# ----------------------------------------------------------------------------- glTF writer

class Gltf:
    def __init__(self, scene_name):
        self.scene_name = scene_name
        self.buffer = bytearray()
        self.buffer_views = []
        self.accessors = []
        self.materials = []
        self.material_index = {}
        self.meshes = []
        self.nodes = []
        self.cameras = []
        self.lights = []
        self.extensions_used = set()
        self.triangles = 0

    def _view(self, data, target):
        while len(self.buffer) % 4:
            self.buffer.append(0)
        offset = len(self.buffer)
        self.buffer += data
        self.buffer_views.append({"buffer": 0, "byteOffset": offset, "byteLength": len(data),
                                  "target": target})
        return len(self.buffer_views) - 1

    def _vec3_accessor(self, values, with_bounds):
        data = b"".join(struct.pack("<3f", *v) for v in values)
        acc = {"bufferView": self._view(data, ARRAY_BUFFER), "componentType": FLOAT,
               "count": len(values), "type": "VEC3"}
        if with_bounds:
            acc["min"] = [min(f32(v[a]) for v in values) for a in range(3)]
            acc["max"] = [max(f32(v[a]) for v in values) for a in range(3)]
        self.accessors.append(acc)
        return len(self.accessors) - 1

    def _index_accessor(self, indices):
        assert max(indices) < 65536
        data = struct.pack("<%dH" % len(indices), *indices)
        self.accessors.append({"bufferView": self._view(data, ELEMENT_ARRAY_BUFFER),
                               "componentType": UNSIGNED_SHORT, "count": len(indices),
                               "type": "SCALAR"})
        return len(self.accessors) - 1

    def material(self, name, base_color, emissive=None, double_sided=False):
        """A rough dielectric: base colour (albedo) rho, optional emitted radiance (W/(m^2 sr))."""
        m = {"name": name,
             "pbrMetallicRoughness": {"baseColorFactor": list(base_color) + [1.0],
                                      "metallicFactor": 0.0, "roughnessFactor": 1.0}}
        if emissive and max(emissive) > 0.0:
            peak = max(emissive)
            if peak > 1.0:
                m["emissiveFactor"] = [c / peak for c in emissive]
                m["extensions"] = {"KHR_materials_emissive_strength": {"emissiveStrength": peak}}
                self.extensions_used.add("KHR_materials_emissive_strength")
            else:
                m["emissiveFactor"] = list(emissive)
        if double_sided:
            m["doubleSided"] = True
        self.materials.append(m)
        self.material_index[name] = len(self.materials) - 1
        return name

    def mesh(self, name, parts):
        """parts: list of (MeshData, material name). Returns the mesh index."""
        prims = []
        for data, mat in parts:
            prims.append({"attributes": {"POSITION": self._vec3_accessor(data.positions, True),
                                         "NORMAL": self._vec3_accessor(data.normals, False)},
                          "indices": self._index_accessor(data.indices),
                          "material": self.material_index[mat], "mode": 4})
        self.meshes.append({"name": name, "primitives": prims})
        return len(self.meshes) - 1

    def node(self, name, mesh=None, translation=None, rotation=None):
        n = {"name": name}
        if mesh is not None:
            n["mesh"] = mesh
            self.triangles += sum(self.accessors[p["indices"]]["count"] // 3
                                  for p in self.meshes[mesh]["primitives"])
        if translation is not None:
            n["translation"] = [float(v) for v in translation]
        if rotation is not None:
            n["rotation"] = [float(v) for v in rotation]
        self.nodes.append(n)
        return len(self.nodes) - 1

    def mesh_node(self, name, parts, translation=None, rotation=None):
        return self.node(name, self.mesh(name, parts), translation, rotation)

    def camera(self, name, eye, target, yfov_degrees):
        self.cameras.append({"name": name, "type": "perspective",
                             "perspective": {"yfov": math.radians(yfov_degrees), "znear": 0.01}})
        n = self.node(name, translation=eye, rotation=look_at_rotation(eye, target))
        self.nodes[n]["camera"] = len(self.cameras) - 1
        return n

    def point_light(self, name, position, intensity, color=(1.0, 1.0, 1.0)):
        """intensity: radiant intensity in W/sr (glTF's candela read radiometrically)."""
        self.lights.append({"name": name, "type": "point", "color": list(color),
                            "intensity": intensity})
        n = self.node(name, translation=position)
        self.nodes[n]["extensions"] = {"KHR_lights_punctual": {"light": len(self.lights) - 1}}
        self.extensions_used.add("KHR_lights_punctual")
        return n

    def to_json(self, extras):
        while len(self.buffer) % 4:
            self.buffer.append(0)
        uri = "data:application/octet-stream;base64," + base64.b64encode(bytes(self.buffer)).decode()
        doc = {"asset": {"version": "2.0", "generator": GENERATOR, "extras": extras},
               "scene": 0,
               "scenes": [{"name": self.scene_name, "nodes": list(range(len(self.nodes)))}],
               "nodes": self.nodes,
               "meshes": self.meshes,
               "materials": self.materials,
               "cameras": self.cameras,
               "accessors": self.accessors,
               "bufferViews": self.buffer_views,
               "buffers": [{"name": self.scene_name + "_data", "byteLength": len(self.buffer),
                            "uri": uri}]}
        if self.lights:
            doc["extensions"] = {"KHR_lights_punctual": {"lights": self.lights}}
        if self.extensions_used:
            doc["extensionsUsed"] = sorted(self.extensions_used)
        return doc

    def write(self, file_name, extras):
        path = os.path.join(OUT_DIR, file_name)
        text = json.dumps(self.to_json(extras), indent=1) + "\n"
        with open(path, "w", encoding="utf-8", newline="\n") as f:
            f.write(text)
        print("%-22s %6d bytes  %4d triangles  %d nodes" %
              (file_name, len(text.encode()), self.triangles, len(self.nodes)))


# ----------------------------------------------------------------------------- scenes

WHITE = (0.725, 0.71, 0.68)
RED = (0.63, 0.065, 0.05)
GREEN = (0.14, 0.45, 0.091)


def cornell_box():
    """Cornell box, 2 m interior: x, z in [-1, 1], y in [0, 2], open towards +z."""
    g = Gltf("cornell_box")
    g.material("cornell_white", WHITE)
    g.material("cornell_red", RED)
    g.material("cornell_green", GREEN)
    lo, hi = (-1.0, 0.0, -1.0), (1.0, 2.0, 1.0)
    walls = [("floor", 1, 0.0, 1, "cornell_white"),
             ("ceiling", 1, 2.0, -1, "cornell_white"),
             ("back_wall", 2, -1.0, 1, "cornell_white"),
             ("left_wall_red", 0, -1.0, 1, "cornell_red"),
             ("right_wall_green", 0, 1.0, -1, "cornell_green")]
    for name, axis, value, sign, mat in walls:
        m = MeshData()
        m.rect(axis, value, lo, hi, sign)
        g.mesh_node(name, [(m, mat)])
    # The classic blocks (Cornell data, 555 mm box scaled to 2 m), base centre on the floor.
    g.mesh_node("short_box", [(box((-0.3, 0.0, -0.3), (0.3, 0.6, 0.3)), "cornell_white")],
                translation=(0.33, 0.0, 0.39), rotation=quat_y(-17.0))
    g.mesh_node("tall_box", [(box((-0.3, 0.0, -0.3), (0.3, 1.2, 0.3)), "cornell_white")],
                translation=(-0.33, 0.0, -0.26), rotation=quat_y(17.0))
    g.point_light("ceiling_light", (0.0, 1.9, 0.0), 3.0)
    g.camera("camera", (0.0, 1.0, 3.4), (0.0, 1.0, 0.0), 40.0)
    g.write("cornell_box.gltf", {
        "purpose": "Built-in default scene: classic Cornell box lit by one point light.",
        "interior": {"min": list(lo), "max": list(hi), "open_side": "+z"}})


# Two rooms: one closed shell x in [SHELL_X0, SHELL_X1], y in [0, ROOM_H], z in [-ROOM_D/2,
# ROOM_D/2], split by a thin wall centred on x = 0. The shell is deliberately off-centre in x
# (4.1 m lit room, 3.9 m dark room) so that a probe grid fitted to the bounds with a common
# spacing (1, 0.5, 0.25 m) does not put a probe plane inside the 2 cm wall.
SHELL_X0, SHELL_X1 = -4.1, 3.9
ROOM_H, ROOM_D = 3.0, 4.0
WALL_T = 0.02
DOOR_W, DOOR_H = 0.9, 2.0


def two_room_shell(g):
    """The outer shell every two-room scene shares: two cells (lit x < 0, dark x > 0), faces
    pointing into the rooms, each with its own material."""
    g.material("lit_room_white", (0.75, 0.75, 0.75))
    g.material("dark_room_white", (0.75, 0.75, 0.75))
    zd = ROOM_D / 2.0
    shell = cell_faces([[SHELL_X0, 0.0, SHELL_X1], [0.0, ROOM_H], [-zd, zd]],
                       lambda i, j, k: True, inward=True,
                       material_of=lambda i, j, k: "lit_room_white" if i == 0 else "dark_room_white")
    g.mesh_node("rooms_shell", [(shell["lit_room_white"], "lit_room_white"),
                                (shell["dark_room_white"], "dark_room_white")])


def two_room_light_and_camera(g):
    """The light in the lit room, and the camera in the dark room looking at the shared wall."""
    g.point_light("lit_room_light", (-2.05, 2.5, 0.0), 10.0)
    g.camera("camera", (3.4, 1.6, 1.6), (0.0, 1.0, -0.1), 60.0)


def two_rooms(open_door):
    name = "two_rooms_open" if open_door else "two_rooms_closed"
    g = Gltf(name)
    two_room_shell(g)
    g.material("shared_wall_white", (0.75, 0.75, 0.75))
    g.material("door_grey", (0.6, 0.6, 0.6))
    zd = ROOM_D / 2.0
    # Shared wall: a closed slab x in [-t/2, t/2] with a doorway cut out of it (the cell
    # z in [-w/2, w/2], y in [0, h] is empty).
    t2, w2 = WALL_T / 2.0, DOOR_W / 2.0
    wall = cell_faces([[-t2, t2], [0.0, DOOR_H, ROOM_H], [-zd, -w2, w2, zd]],
                      lambda i, j, k: not (j == 0 and k == 1))[None]
    g.mesh_node("shared_wall", [(wall, "shared_wall_white")])
    # Door: the closed slab that fills the doorway. Its node origin is the hinge, the vertical
    # edge at x = +t/2 (dark-room side), z = -w/2. Opening turns it +90 degrees about +Y into
    # the dark room, where it stands perpendicular to the wall along x in [t/2, t/2 + w].
    door = box((-WALL_T, 0.0, 0.0), (0.0, DOOR_H, DOOR_W))
    g.mesh_node("door", [(door, "door_grey")], translation=(t2, 0.0, -w2),
                rotation=quat_y(90.0) if open_door else [0.0, 0.0, 0.0, 1.0])
    two_room_light_and_camera(g)
    g.write(name + ".gltf", {
        "purpose": "Light-leak test: a lit room and a dark room share a 2 cm wall with a "
                   "doorway; the door node is " + ("open." if open_door else "closed."),
        "shell": {"min": [SHELL_X0, 0.0, -zd], "max": [SHELL_X1, ROOM_H, zd]},
        "shared_wall": {"x": [-t2, t2]},
        "doorway": {"x": [-t2, t2], "y": [0.0, DOOR_H], "z": [-w2, w2]},
        "lit_room_x": [SHELL_X0, -t2], "dark_room_x": [t2, SHELL_X1]})


def two_rooms_plane_wall():
    """The closed two rooms with the 2 cm slab replaced by the thinnest wall there is: one
    double-sided quad in the plane x = 0, as game art models partitions. A probe in that plane
    sees both rooms, the classic light leak that relocation must fix."""
    g = Gltf("two_rooms_plane_wall")
    two_room_shell(g)
    g.material("plane_wall_white", (0.75, 0.75, 0.75), double_sided=True)
    zd = ROOM_D / 2.0
    wall = MeshData()
    wall.rect(0, 0.0, (0.0, 0.0, -zd), (0.0, ROOM_H, zd), -1)  # front face towards the light
    g.mesh_node("plane_wall", [(wall, "plane_wall_white")])
    two_room_light_and_camera(g)
    g.write("two_rooms_plane_wall.gltf", {
        "purpose": "Light-leak test: a lit room and a dark room split by a zero-thickness, "
                   "double-sided wall (one quad at x = 0, no doorway).",
        "shell": {"min": [SHELL_X0, 0.0, -zd], "max": [SHELL_X1, ROOM_H, zd]},
        "plane_wall": {"x": 0.0, "double_sided": True},
        "lit_room_x": [SHELL_X0, 0.0], "dark_room_x": [0.0, SHELL_X1]})


def white_box():
    """White furnace: closed box, every face emits Le = 1 and reflects rho = 0.5."""
    g = Gltf("white_box")
    g.material("furnace_white", (0.5, 0.5, 0.5), emissive=(1.0, 1.0, 1.0))
    lo, hi = (-1.0, 0.0, -1.0), (1.0, 2.0, 1.0)
    g.mesh_node("furnace_box", [(box(lo, hi, inward=True), "furnace_white")])
    g.camera("camera", (0.0, 1.0, 0.8), (0.0, 1.0, -1.0), 60.0)
    g.write("white_box.gltf", {
        "purpose": "White-furnace test: expected radiance everywhere inside is Le / (1 - rho) "
                   "= 2 for rho = 0.5 (1.25 for 0.2, 5 for 0.8).",
        "interior": {"min": list(lo), "max": list(hi)}})


def box_on_floor():
    """A 1 m cube on an 8 x 8 m floor, lit from above and to the side (-x)."""
    g = Gltf("box_on_floor")
    g.material("floor_white", (0.8, 0.8, 0.8))
    g.material("occluder_white", (0.8, 0.8, 0.8))
    floor = MeshData()
    floor.rect(1, 0.0, (-4.0, 0.0, -4.0), (4.0, 0.0, 4.0), 1)
    g.mesh_node("floor", [(floor, "floor_white")])
    g.mesh_node("occluder", [(box((-0.5, 0.0, -0.5), (0.5, 1.0, 0.5)), "occluder_white")])
    g.point_light("key_light", (-1.5, 2.5, 0.0), 20.0)
    g.camera("camera", (3.5, 3.0, 3.5), (1.0, 0.0, 0.0), 45.0)
    g.write("box_on_floor.gltf", {
        "purpose": "Shadow test: the cube's shadow on the floor, no walls, black environment.",
        "shadow_on_floor": "the hexagon (-0.5,+-0.5), (1/6,+-5/6), (11/6,+-5/6) in (x, z) minus "
                           "the cube's footprint; beyond the cube: x in [0.5, 11/6], |z| <= 5/6"})


STREET_HALF_LENGTH = 200.0   # the street runs along x in [-200, 200]
STREET_HALF_WIDTH = 6.0      # facades at z = +-6
BUILDING_DEPTH = 10.0
BUILDING_WIDTH = 16.0
BUILDING_GAP = 4.0
BUILDING_WALL = 0.3
STREET_DOOR_W, STREET_DOOR_H = 2.0, 3.0
PLASTER = [(0.75, 0.70, 0.62), (0.62, 0.66, 0.70), (0.78, 0.60, 0.50), (0.55, 0.62, 0.52)]


def street_building(x0, side, height):
    """A hollow building of one hall, its facade on the street (z = side * 6) with an open
    doorway in its middle; walls and roof BUILDING_WALL thick, closed surfaces facing out (the
    hall's faces face into it). side: +1 north of the street, -1 south."""
    t = BUILDING_WALL
    x1 = x0 + BUILDING_WIDTH
    xc = (x0 + x1) / 2.0
    near, far = side * STREET_HALF_WIDTH, side * (STREET_HALF_WIDTH + BUILDING_DEPTH)
    zs = sorted([near, near + side * t, far - side * t, far])
    street_k = 0 if side > 0 else 2  # the cell layer of the street wall
    grid = [[x0, x0 + t, xc - STREET_DOOR_W / 2, xc + STREET_DOOR_W / 2, x1 - t, x1],
            [0.0, STREET_DOOR_H, height - t, height], zs]

    def filled(i, j, k):
        hall = 1 <= i <= 3 and j <= 1 and k == 1
        doorway = i == 2 and j == 0 and k == street_k
        return not hall and not doorway

    return cell_faces(grid, filled)[None]


def street():
    """A street 400 m long between two rows of 20 buildings each (8-20 m high, 16 m wide, 4 m
    apart), every one a hall with an open doorway on the street; neon signs over every fifth
    door. The sun and the sky come from street.ddgi.json. A scene larger than any one probe grid
    of room-scale spacing can cover (docs/cascades.md)."""
    g = Gltf("street")
    g.material("asphalt", (0.25, 0.25, 0.25))
    for n, colour in enumerate(PLASTER):
        g.material("plaster_%d" % n, colour)
    g.material("neon_warm", (0.8, 0.8, 0.8), emissive=(1.0, 0.45, 0.15))
    g.material("neon_cold", (0.8, 0.8, 0.8), emissive=(0.2, 0.6, 1.0))
    ground = MeshData()
    extent = STREET_HALF_WIDTH + BUILDING_DEPTH + 4.0
    ground.rect(1, 0.0, (-STREET_HALF_LENGTH, 0.0, -extent), (STREET_HALF_LENGTH, 0.0, extent), 1)
    g.mesh_node("ground", [(ground, "asphalt")])
    pitch = BUILDING_WIDTH + BUILDING_GAP
    count = int(2 * STREET_HALF_LENGTH / pitch)
    signs = 0
    for side in (1, -1):
        for b in range(count):
            x0 = -STREET_HALF_LENGTH + BUILDING_GAP / 2 + b * pitch
            height = 8.0 + 4.0 * ((b * 7 + (3 if side > 0 else 0)) % 4)
            name = "building_%s_%02d" % ("north" if side > 0 else "south", b)
            g.mesh_node(name, [(street_building(x0, side, height),
                                "plaster_%d" % ((b + (side > 0)) % len(PLASTER)))])
            if (b + (2 if side > 0 else 0)) % 5 == 0:
                # A 4 x 1 m sign 5 cm in front of the facade, over the door, facing the street.
                xc = x0 + BUILDING_WIDTH / 2
                z = side * (STREET_HALF_WIDTH - 0.05)
                sign = MeshData()
                sign.rect(2, z, (xc - 2.0, 3.6, 0.0), (xc + 2.0, 4.6, 0.0), -side)
                g.mesh_node("sign_%d" % signs, [(sign, "neon_warm" if signs % 2 else "neon_cold")])
                signs += 1
    g.camera("camera", (-180.0, 1.7, 0.0), (-170.0, 1.7, 0.0), 60.0)
    g.write("street.gltf", {
        "purpose": "Large-scene test (issue 17): a 400 m street between two rows of halls with "
                   "open doorways and neon signs; sun and sky in street.ddgi.json; a camera "
                   "path in street.path.json.",
        "street": {"x": [-STREET_HALF_LENGTH, STREET_HALF_LENGTH],
                   "facades_z": [-STREET_HALF_WIDTH, STREET_HALF_WIDTH]},
        "buildings": 2 * count, "signs": signs})
    street_path()


def street_path():
    """A walk along the street at eye height, into the hall north of x in [-2, 14] through its
    doorway, a turn on the spot at its back (the view never passes through the camera or the
    vertical: readers refuse such paths) and out again, then on: keyframes of position and
    look-at target, walking at 1.4 m/s, each quarter turn taking 1.5 s."""
    eye = 1.7
    door_x = -STREET_HALF_LENGTH + BUILDING_GAP / 2 + 10 * (BUILDING_WIDTH + BUILDING_GAP) + \
        BUILDING_WIDTH / 2
    entry, back = (door_x, eye, 3.0), (door_x, eye, STREET_HALF_WIDTH + 4.0)
    out, end = (door_x + 6.0, eye, 0.0), (180.0, eye, 0.0)

    def ahead(p, dx, dz):
        return (p[0] + dx, p[1], p[2] + dz)
    # (position, target); consecutive equal positions are turns.
    poses = [((-180.0, eye, 0.0), (door_x - 6.0, eye, 0.0)),
             ((door_x - 6.0, eye, 0.0), entry), (entry, back), (back, ahead(back, 0, 10)),
             (back, ahead(back, 10, 0)), (back, entry), (entry, out), (out, end),
             (end, ahead(end, 10, 0))]
    keys, t = [], 0.0
    for n, (p, target) in enumerate(poses):
        if n > 0:
            moved = math.dist(p, poses[n - 1][0])
            t += moved / 1.4 if moved > 0 else 1.5
        keys.append({"time": round(t, 3), "position": list(p), "target": list(target)})
    path = {"scene": "street.ddgi.json",
            "description": "A walk along the street at eye height, into a hall and out, 1.4 m/s; "
                           "position and look-at target are linear between keyframes.",
            "keyframes": keys}
    file_name = os.path.join(OUT_DIR, "street.path.json")
    with open(file_name, "w", encoding="utf-8", newline="\n") as f:
        f.write(json.dumps(path, indent=1) + "\n")
    print("%-22s %d keyframes, %.0f s" % ("street.path.json", len(keys), t))


def main():
    cornell_box()
    two_rooms(open_door=False)
    two_rooms(open_door=True)
    two_rooms_plane_wall()
    white_box()
    box_on_floor()
    street()


if __name__ == "__main__":
    main()
