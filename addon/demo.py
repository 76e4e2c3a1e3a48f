"""The built-in demo scene: the Cornell box, built in code (no external file).

Geometry and reflectances are those of McGuire's CornellBox-Original.obj, converted to Blender's z-up axes as
shared/scenes/setups/cornell.py does (x = x_obj, y = -z_obj, z = y_obj), so renders compare with that setup:
  - the two 'Bottom Face' faces of the file are left out (they duplicate the short box's right face and the tall
    box's front face by a mistake in the file), and so is the emissive quad: 15 quads, 30 triangles;
  - the quad becomes a rectangular area light of the same size and centre, pointing down, whose radiance is the
    OBJ's Ke = (17, 12, 4) with colour (1, 12/17, 4/17): Cycles' area radiance is P / (4 A) in Blender 3.x, so
    P = 4 A 17 W there as in cornell.py, and P / (pi A) from 4.0, so P = pi A 17 W (the factor Blender itself
    applies when it loads a 3.x file);
  - materials are Diffuse BSDFs (roughness 0: Lambertian) with the OBJ's Kd;
  - camera at (0, -6.8, 1) looking +Y with a 19.5 degree field of view, black world, square resolution.
"""
import math

import bpy
from mathutils import Vector

from .export.lights import area_radiance_per_watt

SCENE_NAME = "Bounce Demo: Cornell Box"

# OBJ vertices (y up), face by face, in the file's order; each face keeps the file's vertex order.
_WHITE = (0.725, 0.71, 0.68)
_MATERIALS = (  # name, Kd
    ("floor", _WHITE), ("ceiling", _WHITE), ("backWall", _WHITE),
    ("rightWall", (0.14, 0.45, 0.091)), ("leftWall", (0.63, 0.065, 0.05)),
    ("shortBox", _WHITE), ("tallBox", _WHITE),
)
_FACES = (  # material index, 4 OBJ vertices
    (0, ((-1.01, 0.00, 0.99), (1.00, 0.00, 0.99), (1.00, 0.00, -1.04), (-0.99, 0.00, -1.04))),
    (1, ((-1.02, 1.99, 0.99), (-1.02, 1.99, -1.04), (1.00, 1.99, -1.04), (1.00, 1.99, 0.99))),
    (2, ((-0.99, 0.00, -1.04), (1.00, 0.00, -1.04), (1.00, 1.99, -1.04), (-1.02, 1.99, -1.04))),
    (3, ((1.00, 0.00, -1.04), (1.00, 0.00, 0.99), (1.00, 1.99, 0.99), (1.00, 1.99, -1.04))),
    (4, ((-1.01, 0.00, 0.99), (-0.99, 0.00, -1.04), (-1.02, 1.99, -1.04), (-1.02, 1.99, 0.99))),
    # short box: top, left, front, right, back
    (5, ((0.53, 0.60, 0.75), (0.70, 0.60, 0.17), (0.13, 0.60, 0.00), (-0.05, 0.60, 0.57))),
    (5, ((-0.05, 0.00, 0.57), (-0.05, 0.60, 0.57), (0.13, 0.60, 0.00), (0.13, 0.00, 0.00))),
    (5, ((0.53, 0.00, 0.75), (0.53, 0.60, 0.75), (-0.05, 0.60, 0.57), (-0.05, 0.00, 0.57))),
    (5, ((0.70, 0.00, 0.17), (0.70, 0.60, 0.17), (0.53, 0.60, 0.75), (0.53, 0.00, 0.75))),
    (5, ((0.13, 0.00, 0.00), (0.13, 0.60, 0.00), (0.70, 0.60, 0.17), (0.70, 0.00, 0.17))),
    # tall box: top, left, back, right, front
    (6, ((-0.53, 1.20, 0.09), (0.04, 1.20, -0.09), (-0.14, 1.20, -0.67), (-0.71, 1.20, -0.49))),
    (6, ((-0.53, 0.00, 0.09), (-0.53, 1.20, 0.09), (-0.71, 1.20, -0.49), (-0.71, 0.00, -0.49))),
    (6, ((-0.71, 0.00, -0.49), (-0.71, 1.20, -0.49), (-0.14, 1.20, -0.67), (-0.14, 0.00, -0.67))),
    (6, ((-0.14, 0.00, -0.67), (-0.14, 1.20, -0.67), (0.04, 1.20, -0.09), (0.04, 0.00, -0.09))),
    (6, ((0.04, 0.00, -0.09), (0.04, 1.20, -0.09), (-0.53, 1.20, 0.09), (-0.53, 0.00, 0.09))),
)
_LIGHT_QUAD = ((-0.24, 1.98, 0.16), (-0.24, 1.98, -0.22), (0.23, 1.98, -0.22), (0.23, 1.98, 0.16))
KE = (17.0, 12.0, 4.0)

CAMERA_LOCATION = (0.0, -6.8, 1.0)
CAMERA_TARGET = (0.0, 0.0, 1.0)
CAMERA_FOV_DEGREES = 19.5


def z_up(vertex):
    """OBJ (y up) -> Blender (z up), as the OBJ importer with forward -Z, up Y."""
    x, y, z = vertex
    return (x, -z, y)


def build(scene, resolution=256):
    """Fill `scene` (expected empty) with the Cornell box and set it to render with Bounce, first bounce included
    (Forward Light Cuts, Preview quality)."""
    _add_box(scene)
    _add_light(scene)
    _add_camera(scene)
    _set_black_world(scene)
    render = scene.render
    render.resolution_x = render.resolution_y = resolution
    render.resolution_percentage = 100
    render.pixel_aspect_x = render.pixel_aspect_y = 1.0
    scene.frame_start = scene.frame_end = scene.frame_current = 1
    render.engine = "BOUNCE"
    scene.bounce.method = "FLC"


def _add_box(scene):
    vertices, faces = [], []
    for _material, quad in _FACES:
        faces.append(tuple(range(len(vertices), len(vertices) + 4)))
        vertices.extend(z_up(v) for v in quad)
    mesh = bpy.data.meshes.new("CornellBox")
    mesh.from_pydata(vertices, [], faces)
    for name, kd in _MATERIALS:
        mesh.materials.append(_diffuse_material(name, kd))
    mesh.polygons.foreach_set("material_index", [material for material, _quad in _FACES])
    mesh.update()
    scene.collection.objects.link(bpy.data.objects.new("CornellBox", mesh))


def _diffuse_material(name, color):
    material = bpy.data.materials.new(name)
    material.diffuse_color = (*color, 1.0)
    if material.node_tree is None:  # Blender < 5.0 makes node trees on request (5.0 deprecates use_nodes)
        material.use_nodes = True
    nodes = material.node_tree.nodes
    nodes.clear()
    output = nodes.new("ShaderNodeOutputMaterial")
    diffuse = nodes.new("ShaderNodeBsdfDiffuse")
    diffuse.location = (output.location.x - 300, output.location.y)
    diffuse.inputs["Color"].default_value = (*color, 1.0)
    diffuse.inputs["Roughness"].default_value = 0.0  # Lambertian
    material.node_tree.links.new(diffuse.outputs["BSDF"], output.inputs["Surface"])
    return material


def _add_light(scene):
    corners = [Vector(z_up(v)) for v in _LIGHT_QUAD]
    low = Vector([min(c[i] for c in corners) for i in range(3)])
    high = Vector([max(c[i] for c in corners) for i in range(3)])
    size_x, size_y = high.x - low.x, high.y - low.y
    light = bpy.data.lights.new("CeilingLight", type="AREA")
    light.shape = "RECTANGLE"
    light.size, light.size_y = size_x, size_y
    light.color = (1.0, KE[1] / KE[0], KE[2] / KE[0])
    light.energy = KE[0] / area_radiance_per_watt(size_x * size_y)  # radiance Ke.r for the white-normalised colour
    obj = bpy.data.objects.new("CeilingLight", light)
    obj.location = (low + high) * 0.5
    obj.rotation_euler = (0.0, 0.0, 0.0)  # area lights emit along local -Z: straight down
    scene.collection.objects.link(obj)


def _add_camera(scene):
    camera = bpy.data.cameras.new("Camera")
    camera.type = "PERSP"
    camera.sensor_fit = "AUTO"
    camera.angle = math.radians(CAMERA_FOV_DEGREES)
    camera.clip_start, camera.clip_end = 0.01, 1000.0
    obj = bpy.data.objects.new("Camera", camera)
    obj.location = CAMERA_LOCATION
    obj.rotation_euler = (Vector(CAMERA_TARGET) - Vector(CAMERA_LOCATION)).to_track_quat("-Z", "Y").to_euler()
    scene.collection.objects.link(obj)
    scene.camera = obj


def _set_black_world(scene):
    world = bpy.data.worlds.new("Black")
    world.color = (0.0, 0.0, 0.0)
    if world.node_tree is None:
        world.use_nodes = True
    nodes = world.node_tree.nodes
    background = next((n for n in nodes if n.type == "BACKGROUND"), None) or nodes.new("ShaderNodeBackground")
    output = next((n for n in nodes if n.type == "OUTPUT_WORLD"), None) or nodes.new("ShaderNodeOutputWorld")
    if not output.inputs["Surface"].is_linked:
        world.node_tree.links.new(background.outputs["Background"], output.inputs["Surface"])
    background.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    background.inputs["Strength"].default_value = 0.0
    scene.world = world
