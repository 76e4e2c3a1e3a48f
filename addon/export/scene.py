"""SceneSync: keeps one native engine's scene in step with a Blender depsgraph.

The first sync exports everything. Later syncs (the viewport's view_update) read depsgraph.updates: geometry is
re-read only for the objects and meshes whose geometry changed; the instance list, material table, lights and
world are rebuilt (cheap) and re-sent only when their bytes differ from what was sent last. So moving an object
re-sends the instance list only, and moving a light re-sends the lights only.
"""
import time
from dataclasses import dataclass, field

import bpy
import numpy as np

from .. import native
from .lights import convert_light
from .materials import MISSING_IMAGE_COLOR, describe_material
from .meshes import UNSUPPORTED_TYPES, column_major, draws_geometry, geometry_key, read_mesh, slot_materials
from .stats import SyncStats
from .textures import read_image
from .world import convert_world

_GEOMETRY_DATA_TYPES = (bpy.types.Mesh, bpy.types.Curve, bpy.types.MetaBall)
_SHADING_TYPES = (bpy.types.Material, bpy.types.NodeTree, bpy.types.Texture, bpy.types.Image)


@dataclass
class _Dirty:
    """What changed since the last sync."""
    everything: bool = False
    geometry: set = field(default_factory=set)   # as_pointer() of objects and geometry datablocks
    images: set = field(default_factory=set)     # as_pointer() of original images
    shading: bool = False                        # a material, node tree or image changed

    def geometry_changed(self, owner):
        return self.everything or owner in self.geometry

    def image_changed(self, pointer):
        return self.everything or pointer in self.images


def _dirty_from_updates(depsgraph):
    dirty = _Dirty()
    for update in depsgraph.updates:
        datablock = update.id
        if isinstance(datablock, bpy.types.Object):
            if update.is_updated_geometry:
                original = datablock.original
                dirty.geometry.add(original.as_pointer())
                if original.data is not None:
                    dirty.geometry.add(original.data.as_pointer())
        elif isinstance(datablock, _GEOMETRY_DATA_TYPES):
            dirty.geometry.add(datablock.original.as_pointer())
        elif isinstance(datablock, _SHADING_TYPES):
            dirty.shading = True
            if isinstance(datablock, bpy.types.Image):
                dirty.images.add(datablock.original.as_pointer())
    return dirty


@dataclass
class _Geometry:
    native_key: int
    triangle_count: int  # 0: nothing drawable, not uploaded


class _InstanceLists:
    def __init__(self):
        self.mesh_keys, self.matrices = [], []
        self.slot_offsets, self.slot_counts, self.slot_materials = [], [], []

    def add(self, native_key, matrix_world, slot_indices):
        self.mesh_keys.append(native_key)
        self.matrices.append(matrix_world)
        self.slot_offsets.append(len(self.slot_materials))
        self.slot_counts.append(len(slot_indices))
        self.slot_materials.extend(slot_indices)

    def arrays(self):
        return (np.array(self.mesh_keys, dtype=np.uint64), column_major(self.matrices),
                np.array(self.slot_offsets, dtype=np.uint32), np.array(self.slot_counts, dtype=np.uint32),
                np.array(self.slot_materials, dtype=np.uint32))


def default_material():
    """Table entry 0: what empty slots draw (Blender's default surface, grey 0.8)."""
    material = native.Material()
    material.base_color[:] = (0.8, 0.8, 0.8)
    material.alpha = 1.0
    material.alpha_threshold = 0.5
    material.double_sided = 1
    return material


class SceneSync:
    """The scene of one native engine. sync() is called once for a final render, on every view_update for the
    viewport. `stats` counts what was sent."""

    def __init__(self, engine):
        self.engine = engine
        self.stats = SyncStats()
        # What the native scene holds (read and updated by _Walk):
        self.geometry = {}         # geometry key -> _Geometry
        self.textures = {}         # original image as_pointer() -> native texture key (NO_TEXTURE: no pixels)
        self.material_cache = {}   # original material as_pointer() -> (native.Material, image pointers), kept
                                   # until a material, node tree or image changes
        self._sent = {}            # table name -> bytes last sent
        self._next_key = 1
        self._synced_depsgraph = None  # as_pointer() of the depsgraph synced last

    def sync(self, depsgraph, reports, moved=False):
        """Bring the native scene up to date; True when anything was sent. A depsgraph other than the last one
        (the next view layer of a final render) is synced in full. `moved`: the caller moved objects or lights
        outside a depsgraph update (a script stepping through frames), so transforms and lights are re-read
        even though the depsgraph lists no update; geometry is not."""
        if self._synced_depsgraph == depsgraph.as_pointer():
            if not depsgraph.updates and not moved:
                return False
            dirty = _dirty_from_updates(depsgraph)
        else:
            dirty = _Dirty(everything=True)
        start = time.perf_counter()
        walk = _Walk(self, dirty, reports)
        walk.run(depsgraph)

        changed = bool(walk.exported)
        changed |= self._send("materials", walk.materials, self.engine.set_materials, "material_syncs")
        instance_arrays = walk.instances.arrays()
        if self._send_bytes("instances", b"".join(a.tobytes() for a in instance_arrays),
                            lambda: self.engine.set_instances(*instance_arrays), "instance_syncs"):
            changed = True
        changed |= self._send("lights", walk.lights, self.engine.set_lights, "light_syncs")
        world = convert_world(depsgraph.scene, reports,
                              lambda image: walk.texture_key(image, image.original.as_pointer()))
        changed |= self._send_bytes("world", bytes(world), lambda: self.engine.set_world(world), "world_syncs")
        changed |= self._remove_unused(walk)

        self._synced_depsgraph = depsgraph.as_pointer()
        self.stats.last_instance_count = len(walk.instances.mesh_keys)
        self.stats.last_light_count = len(walk.lights)
        self.stats.last_light_names = walk.light_names
        self.stats.record_sync(time.perf_counter() - start, walk.geometry_seconds, walk.triangles_exported)
        return changed

    def _send(self, name, structs, setter, counter):
        return self._send_bytes(name, b"".join(bytes(s) for s in structs), lambda: setter(structs), counter)

    def _send_bytes(self, name, payload, send, counter):
        if self._sent.get(name) == payload:
            return False
        send()
        self._sent[name] = payload
        setattr(self.stats, counter, getattr(self.stats, counter) + 1)
        return True

    def _remove_unused(self, walk):
        """Free geometry and textures no instance uses any more (after the new instance list is sent)."""
        removed = False
        for key in [k for k in self.geometry if k not in walk.geometry_used]:
            geometry = self.geometry.pop(key)
            if geometry.triangle_count:
                self.engine.remove_mesh(geometry.native_key)
                self.stats.meshes_removed += 1
                removed = True
        for pointer in [p for p in self.textures if p not in walk.textures_used]:
            texture_key = self.textures.pop(pointer)
            if texture_key != native.NO_TEXTURE:
                self.engine.remove_texture(texture_key)
                removed = True
        return removed

    def new_key(self):
        key = self._next_key
        self._next_key += 1
        return key


class _Walk:
    """One pass over depsgraph.object_instances, exporting what changed and collecting the tables."""

    def __init__(self, sync, dirty, reports):
        self.sync, self.dirty, self.reports = sync, dirty, reports
        self.instances = _InstanceLists()
        self.lights = []
        self.light_names = []
        self.materials = [default_material()]
        self.material_index = {}     # original material as_pointer() -> index in self.materials
        self.slot_tables = {}        # (geometry key, original object) -> material index of each slot
        self.geometry_used, self.exported = set(), set()
        self.textures_used, self.textures_uploaded = set(), set()
        self.geometry_seconds = 0.0
        self.triangles_exported = 0
        if dirty.everything or dirty.shading:
            sync.material_cache.clear()

    def run(self, depsgraph):
        for instance in depsgraph.object_instances:
            obj = instance.object
            if obj.type == "LIGHT":
                light = convert_light(obj.data, instance.matrix_world, self.reports)
                if light is not None:
                    self.lights.append(light)
                    self.light_names.append(obj.name)
            elif draws_geometry(obj):
                if getattr(instance, "show_self", True):
                    self._add_geometry_instance(instance, obj)
            elif obj.type in UNSUPPORTED_TYPES:
                self.reports.warn(f"Bounce does not render {UNSUPPORTED_TYPES[obj.type]} yet; they are skipped")

    def _add_geometry_instance(self, instance, obj):
        key, owner = geometry_key(instance)
        self.geometry_used.add(key)
        geometry = self.sync.geometry.get(key)
        if key not in self.exported and (geometry is None or self.dirty.geometry_changed(owner)):
            geometry = self._export_geometry(key, geometry, obj)
        if geometry.triangle_count:
            # Instances of one object's geometry (geometry nodes, particles) share their slot table.
            slot_key = (key, obj.original.as_pointer())
            slots = self.slot_tables.get(slot_key)
            if slots is None:
                slots = [self._material_index(material) for material in slot_materials(obj)]
                self.slot_tables[slot_key] = slots
            # copy(): the matrix wraps the iterator's memory, which the next instance overwrites
            self.instances.add(geometry.native_key, instance.matrix_world.copy(), slots)

    def _export_geometry(self, key, previous, obj):
        start = time.perf_counter()
        sync = self.sync
        try:
            arrays = read_mesh(obj)
        except RuntimeError as error:  # to_mesh() refuses some objects (e.g. empty curves)
            self.reports.warn(f"Object '{obj.name}' has no usable geometry: {error}")
            arrays = None
        native_key = previous.native_key if previous is not None else sync.new_key()
        if arrays is None:
            if previous is not None and previous.triangle_count:
                sync.engine.remove_mesh(native_key)
            geometry = _Geometry(native_key, 0)
        else:
            sync.engine.set_mesh(native_key, arrays.positions, arrays.triangles, arrays.corner_normals,
                                 arrays.corner_uvs, arrays.triangle_slots)
            sync.stats.meshes_exported += 1
            sync.stats.triangles_exported += arrays.triangle_count
            self.triangles_exported += arrays.triangle_count
            geometry = _Geometry(native_key, arrays.triangle_count)
        sync.geometry[key] = geometry
        self.exported.add(key)
        self.geometry_seconds += time.perf_counter() - start
        return geometry

    def _material_index(self, material):
        if material is None:
            return 0
        pointer = material.original.as_pointer()
        index = self.material_index.get(pointer)
        if index is None:
            index = len(self.materials)
            self.materials.append(self._native_material(material, pointer))
            self.material_index[pointer] = index
        return index

    def _native_material(self, material, pointer):
        cached = self.sync.material_cache.get(pointer)
        if cached is not None:
            native_material, image_pointers = cached
            self.textures_used.update(image_pointers)
            return native_material
        surface = describe_material(material, self.reports)
        out = default_material()
        out.base_color[:] = surface.base_color
        out.alpha = surface.alpha
        out.alpha_threshold = surface.alpha_threshold if surface.alpha_threshold is not None else 0.5
        out.emission[:] = surface.emission
        image_pointers = []

        def texture_of(image):
            """The image's texture key; NO_TEXTURE for none or a missing one (the caller draws magenta)."""
            if image is None:
                return native.NO_TEXTURE
            image_pointers.append(image.original.as_pointer())
            return self.texture_key(image, image_pointers[-1])

        if surface.image is not None:
            out.base_color_texture = texture_of(surface.image)
            if out.base_color_texture == native.NO_TEXTURE:
                out.base_color[:] = MISSING_IMAGE_COLOR
            else:
                out.alpha_from_texture = 1 if surface.alpha_from_texture else 0
        if surface.emission_image is not None:
            out.emission_texture = texture_of(surface.emission_image)
            if out.emission_texture == native.NO_TEXTURE:
                out.emission[:] = tuple(e * m for e, m in zip(surface.emission, MISSING_IMAGE_COLOR))
        self.sync.material_cache[pointer] = (out, tuple(image_pointers))
        return out

    def texture_key(self, image, pointer):
        self.textures_used.add(pointer)
        textures = self.sync.textures
        key = textures.get(pointer)
        if pointer in self.textures_uploaded or (key is not None and not self.dirty.image_changed(pointer)):
            return key
        self.textures_uploaded.add(pointer)
        pixels = read_image(image, self.reports)
        if pixels is None:
            if key:
                self.sync.engine.remove_texture(key)
            textures[pointer] = native.NO_TEXTURE
            return native.NO_TEXTURE
        key = key or self.sync.new_key()
        self.sync.engine.set_texture(key, pixels.width, pixels.height, pixels.format, pixels.pixels)
        self.sync.stats.texture_uploads += 1
        textures[pointer] = key
        return key
