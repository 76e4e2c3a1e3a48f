"""The world and emissive surfaces as lights, Blender side: a Lambertian plane (albedo 0.8) seen straight down by an
orthographic camera, lit by one source per case, rendered with every method into OUT/<case>_<method>.exr; and
OUT/world.json with what each case expects, computed here from Blender's own data:

  sky:     a uniform white world of strength 1: radiance 0.8 everywhere;
  emitter: a 1 m square Emission surface of strength 10, 1 m above the plane (the test computes its view factor);
  textured_emitter: the same, its colour from a one-texel Image Texture: the emitter's light times the texel;
  sky_sun_emitter: a uniform sky of strength 0.5, a sun and the emitter at once, whole and (NAME@SOURCES) lit by
           each class alone (bl_common.keep_light_sources, the benchmark's source split): the shares must add up;
  hdri:    Blender's studio HDRI forest.exr through a Mapping node rotated (30, 0, 45) degrees, strength 0.5: the
           plane's radiance 0.8 / pi x the environment's cosine-weighted integral over the upper hemisphere,
           summed here over the image's pixels (numpy), independently of the add-on and the core.

    blender -b --factory-startup --python world_scene.py -- CASES.json OUT
"""
import math
import os
import sys

import bpy
import numpy as np
from mathutils import Euler

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bl_common as bc  # noqa: E402

HDRI_ROTATION_DEG = (30.0, 0.0, 45.0)
HDRI_STRENGTH = 0.5


def world_nodes(scene):
    world = bpy.data.worlds.new("World")
    world.use_nodes = True
    nodes = world.node_tree.nodes
    nodes.clear()
    background = nodes.new("ShaderNodeBackground")
    output = nodes.new("ShaderNodeOutputWorld")
    world.node_tree.links.new(background.outputs["Background"], output.inputs["Surface"])
    scene.world = world
    return world, background


def uniform_sky(scene):
    _, background = world_nodes(scene)
    background.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    background.inputs["Strength"].default_value = 1.0
    return {"radiance": 0.8}


def hdri_sky(scene):
    world, background = world_nodes(scene)
    nodes, links = world.node_tree.nodes, world.node_tree.links
    path = os.path.join(bpy.utils.system_resource("DATAFILES", path="studiolights"), "world", "forest.exr")
    image = bpy.data.images.load(path)
    environment = nodes.new("ShaderNodeTexEnvironment")
    environment.image = image
    mapping = nodes.new("ShaderNodeMapping")
    mapping.inputs["Rotation"].default_value = [math.radians(a) for a in HDRI_ROTATION_DEG]
    coordinates = nodes.new("ShaderNodeTexCoord")
    links.new(coordinates.outputs["Generated"], mapping.inputs["Vector"])
    links.new(mapping.outputs["Vector"], environment.inputs["Vector"])
    links.new(environment.outputs["Color"], background.inputs["Color"])
    background.inputs["Strength"].default_value = HDRI_STRENGTH
    # The expected radiance: the environment direction e of world direction d is R d (Mapping, type Point).
    width, height = image.size
    pixels = np.empty(width * height * 4, dtype=np.float32)
    image.pixels.foreach_get(pixels)
    radiance = pixels.reshape(height, width, 4)[:, :, :3].astype(np.float64) * HDRI_STRENGTH
    u = (np.arange(width) + 0.5) / width
    v = (np.arange(height) + 0.5) / height
    phi = (0.5 - u[None, :]) * 2.0 * math.pi  # Cycles' equirectangular mapping: u = 0.5 - atan2(y, x) / 2 pi
    elevation = (v[:, None] - 0.5) * math.pi
    e = np.stack([np.cos(phi) * np.cos(elevation), np.sin(phi) * np.cos(elevation),
                  np.sin(elevation) * np.ones_like(phi)], axis=-1)
    rotation = np.array(Euler([math.radians(a) for a in HDRI_ROTATION_DEG], "XYZ").to_matrix())
    d = e @ rotation  # R^T e per row: the world direction
    solid_angle = (2.0 * math.pi / width) * (math.pi / height) * np.cos(elevation)
    irradiance = (radiance * (np.maximum(d[..., 2], 0.0) * solid_angle)[..., None]).sum(axis=(0, 1))
    return {"radiance": list(0.8 / math.pi * irradiance), "image": path}


def emitter(scene, tint=None):
    bc.black_world(scene)
    material = bpy.data.materials.new("Emitter")
    material.use_nodes = True
    nodes = material.node_tree.nodes
    nodes.clear()
    emission = nodes.new("ShaderNodeEmission")
    emission.inputs["Strength"].default_value = 10.0
    output = nodes.new("ShaderNodeOutputMaterial")
    material.node_tree.links.new(emission.outputs["Emission"], output.inputs["Surface"])
    if tint is not None:
        image = bpy.data.images.new("Tint", 1, 1, float_buffer=True)
        image.pixels.foreach_set([*tint, 1.0])
        texture = nodes.new("ShaderNodeTexImage")
        texture.image = image
        material.node_tree.links.new(texture.outputs["Color"], emission.inputs["Color"])
    bc.add_plane(scene, 1.0, z=1.0, material=material, name="Emitter")
    return {"emission": 10.0, "emitter_half": 0.5, "emitter_height": 1.0, "tint": list(tint or (1.0, 1.0, 1.0))}


def textured_emitter(scene):
    """The emitter with its colour from an Image Texture (one texel (0.25, 0.5, 1)): the light takes its colour."""
    return emitter(scene, tint=(0.25, 0.5, 1.0))


def sky_sun_emitter(scene):
    expected = emitter(scene)
    _, background = world_nodes(scene)
    background.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    background.inputs["Strength"].default_value = 0.5
    sun = bpy.data.lights.new("Sun", "SUN")
    sun.energy = 2.0
    sun.angle = math.radians(2.0)
    sun_object = bpy.data.objects.new("Sun", sun)
    sun_object.rotation_euler = (math.radians(30.0), 0.0, math.radians(20.0))
    scene.collection.objects.link(sun_object)
    return expected


CASES = {"sky": uniform_sky, "hdri": hdri_sky, "emitter": emitter, "textured_emitter": textured_emitter,
         "sky_sun_emitter": sky_sun_emitter}


def main():
    cases_path, out = bc.args()[:2]
    spec = bc.load_json(cases_path)
    os.makedirs(out, exist_ok=True)
    record = {"blender": list(bc.version()), "cases": {}}
    for name in spec["cases"]:
        bc.clear_data()
        scene = bpy.context.scene
        bc.add_plane(scene, spec["plane_size"], material=bc.diffuse_material("Plane", (0.8,) * 3))
        bc.add_ortho_camera(scene, spec["center"], spec["camera_height"], spec["ortho_scale"])
        bc.set_resolution(scene, spec["resolution"], spec["resolution"])
        bc.linear_output(scene)
        base, _, sources = name.partition("@")
        expected = CASES[base](scene)
        if sources:
            bc.keep_light_sources(scene, sources)
        renders = {}
        for method in spec["methods"]:
            bc.bounce_settings(scene, **dict(spec["bounce"], method=method))
            bpy.context.view_layer.update()
            renders[method] = bc.render_still(scene, os.path.join(out, f"{name}_{method}"))
            print(f"rendered world case {name} with {method}")
        record["cases"][name] = {"expected": expected, "exr": renders}
    bc.write_json(os.path.join(out, "world.json"), record)


main()
