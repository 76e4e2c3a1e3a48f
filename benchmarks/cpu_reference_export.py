"""Inside Blender (benchmarks/blender_render.py): the open scene as the input of bounce_reference_render, the CPU
model reference of native/reference (the file format is in native/reference/reference_render.cpp).

The scene goes through the add-on's own export (camera, lights, evaluated meshes, materials), so the reference
sees what Bounce sees, with two simplifications the CPU model needs: each triangle gets one albedo, the base colour
times its texture at the triangle's UV centroid (Bounce samples the texture at each VPL and pixel), and a cut-out
triangle is dropped whole when the texture's alpha at its centroid is under the threshold.
"""
import struct
import types

import numpy as np

MAGIC = b"BNCREF1\n"


def _srgb_to_linear(c):
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


class _Albedo:
    """Per-slot albedo and cut-out of the scene's materials, each read once."""

    def __init__(self, addon, reports):
        self.materials, self.textures, self.native = addon("export.materials"), addon("export.textures"), addon("native")
        self.reports, self.cache = reports, {}

    def surface(self, material):
        key = material.original.as_pointer() if material is not None else 0
        if key not in self.cache:
            desc = self.materials.describe_material(material, self.reports)
            pixels = self.textures.read_image(desc.image, self.reports) if desc.image is not None else None
            self.cache[key] = (desc, pixels)
        return self.cache[key]

    def of_triangles(self, material, corner_uvs, indices):
        """(albedo (n, 3), kept (n,) bool) of the triangles `indices` of one slot."""
        desc, pixels = self.surface(material)
        albedo = np.tile(np.asarray(desc.base_color, dtype=np.float32), (len(indices), 1))
        kept = np.ones(len(indices), dtype=bool)
        if desc.image is None:
            return albedo, kept
        if pixels is None or corner_uvs is None:  # missing image: magenta, as Bounce and Cycles draw it
            albedo[:] = self.materials.MISSING_IMAGE_COLOR
            return albedo, kept
        uv = corner_uvs[indices].mean(axis=1)
        x = np.mod(np.floor(uv[:, 0] * pixels.width).astype(np.int64), pixels.width)
        y = np.mod(np.floor(uv[:, 1] * pixels.height).astype(np.int64), pixels.height)
        texels = pixels.pixels.reshape(pixels.height, pixels.width, 4)[y, x].astype(np.float32)
        if pixels.format != self.native.TEXTURE_RGBA32F:
            texels /= 255.0
        rgb = _srgb_to_linear(texels[:, :3]) if pixels.format == self.native.TEXTURE_RGBA8_SRGB else texels[:, :3]
        albedo *= rgb
        if desc.alpha_from_texture:
            threshold = desc.alpha_threshold if desc.alpha_threshold is not None else 0.5
            kept = texels[:, 3] >= threshold
        return albedo, kept


def export(depsgraph, path, addon, points, light_samples):
    """Writes the scene of `depsgraph`, seen by its camera at the render resolution, to `path`. `addon(name)`
    imports an add-on submodule. The model's epsilon is the default flc_epsilon of the settings table, as the
    measured renders use it. Returns (triangles, lights) written."""
    epsilon_fraction = depsgraph.scene.bounce.bl_rna.properties["flc_epsilon"].default
    camera_module, lights_module = addon("export.camera"), addon("export.lights")
    meshes, reports_module = addon("export.meshes"), addon("export.reports")
    reports = reports_module.Reports()
    camera = camera_module.final_camera(types.SimpleNamespace(camera_override=None), depsgraph)
    albedo = _Albedo(addon, reports)
    lights, blocks, cache = [], [], {}
    for instance in depsgraph.object_instances:
        obj = instance.object
        if obj.type == "LIGHT":
            light = lights_module.convert_light(obj.data, instance.matrix_world, reports)
            if light is not None:
                lights.append(light)
            continue
        if not meshes.draws_geometry(obj) or not getattr(instance, "show_self", True):
            continue
        key, _ = meshes.geometry_key(instance)
        if key not in cache:
            cache[key] = meshes.read_mesh(obj)
        arrays = cache[key]
        if arrays is None:
            continue
        matrix = np.array(instance.matrix_world, dtype=np.float64)
        world = arrays.positions.astype(np.float64) @ matrix[:3, :3].T + matrix[:3, 3]
        corners = world[arrays.triangles.astype(np.int64)]  # (T, 3, 3)
        materials = meshes.slot_materials(obj)
        for slot in np.unique(arrays.triangle_slots):
            indices = np.nonzero(arrays.triangle_slots == slot)[0]
            material = materials[slot] if 0 <= slot < len(materials) else None
            colour, kept = albedo.of_triangles(material, arrays.corner_uvs, indices)
            block = np.concatenate([corners[indices].reshape(-1, 9).astype(np.float32), colour], axis=1)
            blocks.append(block[kept])
    for level, message in reports:
        print(f"cpu reference: {level.lower()}: {message}", flush=True)
    triangles = np.concatenate(blocks) if blocks else np.zeros((0, 12), dtype=np.float32)
    native = addon("native")
    with open(path, "wb") as out:
        out.write(MAGIC)
        out.write(struct.pack("<2i", len(bytes(native.Camera())), len(bytes(native.Light()))))
        out.write(struct.pack("<i2f", light_samples, epsilon_fraction, points))
        out.write(bytes(camera))
        out.write(struct.pack("<i", len(lights)))
        for light in lights:
            out.write(bytes(light))
        out.write(struct.pack("<q", len(triangles)))
        out.write(np.ascontiguousarray(triangles, dtype="<f4").tobytes())
    return len(triangles), len(lights)
