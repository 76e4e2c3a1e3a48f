"""Evaluated geometry -> flat numpy arrays for bounce_mesh_set, and the key that lets instances share it."""
from dataclasses import dataclass
from itertools import chain
from typing import Optional

import bpy
import numpy as np
from mathutils import Matrix

# Object types whose own evaluated geometry becomes triangles through Object.to_mesh(). Curve and text objects are
# left out: Blender presents their evaluated geometry as a separate instance of type MESH (as Cycles expects).
_TO_MESH_TYPES = {"SURFACE", "META"}
# Types that carry geometry Bounce does not draw yet: reported once per sync.
UNSUPPORTED_TYPES = {"CURVES": "hair curves", "POINTCLOUD": "point clouds", "VOLUME": "volumes",
                     "GPENCIL": "grease pencil", "GREASEPENCIL": "grease pencil"}


@dataclass
class MeshArrays:
    positions: np.ndarray                 # (V, 3) float32, object space
    triangles: np.ndarray                 # (T, 3) uint32
    corner_normals: np.ndarray            # (T, 3, 3) float32 split normals
    corner_uvs: Optional[np.ndarray]      # (T, 3, 2) float32, active UV map, or None
    triangle_slots: np.ndarray            # (T,) int32 material slot index

    @property
    def triangle_count(self):
        return len(self.triangles)


def draws_geometry(obj):
    """Whether the triangles of an evaluated object are exported."""
    return isinstance(obj.data, bpy.types.Mesh) or obj.type in _TO_MESH_TYPES


def geometry_key(instance):
    """A hashable key of the geometry an object instance draws, equal for instances that can share one upload.

    Objects without modifiers draw their mesh datablock unchanged, so they (and collection/vertex instances of
    them) share it: the key is the original mesh. Anything else (modifiers, curves, geometry-node output) gets a
    key of its own, made of the object that owns the evaluation and the evaluated data, which is shared by the
    geometry-node instances of one piece of geometry.
    Returns (key, owner): `owner` is the as_pointer() of the datablock whose update invalidates the geometry.
    """
    obj = instance.object
    original = obj.original
    if obj.type == "MESH" and original.type == "MESH" and len(original.modifiers) == 0 and original.data:
        mesh_pointer = original.data.as_pointer()
        return ("mesh", mesh_pointer), mesh_pointer
    owner = original.as_pointer()
    data = obj.data
    return ("evaluated", owner, data.as_pointer() if data is not None else 0), owner


def read_mesh(obj):
    """The triangles of an evaluated object as MeshArrays; None when it has none."""
    mesh = obj.to_mesh()
    if mesh is None:
        return None
    try:
        return _read_triangles(mesh)
    finally:
        obj.to_mesh_clear()


def _read_triangles(mesh):
    mesh.calc_loop_triangles()
    triangle_count = len(mesh.loop_triangles)
    if triangle_count == 0:
        return None
    corners = _foreach(mesh.loop_triangles, "loops", 3 * triangle_count, np.int32)
    # Blender 4.x exposes corner and face data as plain arrays (fast); 3.x computes per triangle through RNA.
    corner_vertices = _attribute(mesh, ".corner_vert", "value", 1, np.int32)
    if corner_vertices is not None:
        triangles = corner_vertices[corners]
    else:
        triangles = _foreach(mesh.loop_triangles, "vertices", 3 * triangle_count, np.int32)

    if hasattr(mesh, "corner_normals"):  # 4.1+
        loop_normals = _foreach(mesh.corner_normals, "vector", 3 * len(mesh.loops), np.float32)
        corner_normals = loop_normals.reshape(-1, 3)[corners]
    else:
        mesh.calc_normals_split()
        corner_normals = _foreach(mesh.loop_triangles, "split_normals", 9 * triangle_count, np.float32)

    if hasattr(mesh, "loop_triangle_polygons"):
        faces = _foreach(mesh.loop_triangle_polygons, "value", triangle_count, np.int32)
        face_materials = _attribute(mesh, "material_index", "value", 1, np.int32)
        slots = face_materials[faces] if face_materials is not None else np.zeros(triangle_count, dtype=np.int32)
    else:
        slots = _foreach(mesh.loop_triangles, "material_index", triangle_count, np.int32)

    positions = _attribute(mesh, "position", "vector", 3, np.float32)
    if positions is None:
        positions = _foreach(mesh.vertices, "co", 3 * len(mesh.vertices), np.float32)

    corner_uvs = None
    uv_layer = mesh.uv_layers.active
    if uv_layer is not None:
        uv_values = getattr(uv_layer, "uv", None)  # 3.5+; `data` is deprecated there
        if uv_values is not None:
            loop_uvs = _foreach(uv_values, "vector", 2 * len(mesh.loops), np.float32)
        else:
            loop_uvs = _foreach(uv_layer.data, "uv", 2 * len(mesh.loops), np.float32)
        corner_uvs = loop_uvs.reshape(-1, 2)[corners].reshape(triangle_count, 3, 2)

    return MeshArrays(positions=positions.reshape(-1, 3),
                      triangles=triangles.view(np.uint32).reshape(-1, 3),
                      corner_normals=corner_normals.reshape(triangle_count, 3, 3),
                      corner_uvs=corner_uvs,
                      triangle_slots=slots)


def _foreach(collection, name, count, dtype):
    values = np.empty(count, dtype=dtype)
    collection.foreach_get(name, values)
    return values


def _attribute(mesh, name, field, width, dtype):
    """A mesh attribute as a flat array, or None where the mesh has no such attribute (3.x, or unset)."""
    attribute = mesh.attributes.get(name)
    if attribute is None:
        return None
    return _foreach(attribute.data, field, width * len(attribute.data), dtype)


def slot_materials(obj):
    """The material of each slot of an evaluated object (None for an empty slot), object- or data-linked as the
    slot says. Geometry made by geometry nodes may carry more materials than the object has slots."""
    materials = [slot.material for slot in obj.material_slots]
    data_materials = getattr(obj.data, "materials", None)
    if data_materials is not None and len(data_materials) > len(materials):
        materials.extend(data_materials[len(materials):])
    return materials


def _has_buffer_protocol(value):
    try:
        memoryview(value)
    except TypeError:
        return False
    return True


# mathutils matrices expose their floats as a buffer in newer Blender (numpy reads them at C speed); in 3.x numpy
# would go through the sequence protocol, ten times slower than chaining the rows.
_MATRIX_IS_BUFFER = _has_buffer_protocol(Matrix())


def column_major(matrices):
    """(N, 16) float32 column-major from a list of 4x4 mathutils matrices (Blender's are row-major)."""
    if _MATRIX_IS_BUFFER:
        rows = np.array(matrices, dtype=np.float32).reshape(-1, 4, 4)
    else:
        rows = np.fromiter(chain.from_iterable(chain.from_iterable(matrices)), dtype=np.float32,
                           count=16 * len(matrices)).reshape(-1, 4, 4)
    return np.ascontiguousarray(rows.transpose(0, 2, 1)).reshape(-1, 16)
