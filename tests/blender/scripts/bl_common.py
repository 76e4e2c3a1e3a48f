"""Helpers for the Blender-side test scripts (run inside Blender 3.4 - 5.2 with --python).

Every script takes its arguments after `--` and writes its results (EXR, JSON) into a folder the pytest side
reads. Nothing here asserts: checks belong to the pytest side.
"""
import importlib
import json
import os
import sys

import bpy


def args():
    """The arguments after '--' on Blender's command line."""
    return sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []


def addon_module(name):
    """The add-on's submodule `name` (e.g. "native", "export.lights"), as a legacy add-on or as an extension."""
    for package in ("bounce", "bl_ext.user_default.bounce"):
        if package in sys.modules:
            return importlib.import_module(f"{package}.{name}")
    raise RuntimeError("the Bounce add-on is not enabled (run through scripts/blender)")


def version():
    return tuple(bpy.app.version)


def view_3d():
    """(window, area, region): the first window, its largest 3D view and that view's drawing region (GUI Blender)."""
    window = bpy.context.window_manager.windows[0]
    area = max((a for a in window.screen.areas if a.type == "VIEW_3D"), key=lambda a: a.width * a.height)
    return window, area, next(r for r in area.regions if r.type == "WINDOW")


def viewport_session():
    """The add-on's session of the viewport's render engine, None while Rendered shading has not started one."""
    sessions = addon_module("session").viewport_sessions()
    return sessions[0] if sessions else None


def load_json(path):
    with open(path) as f:
        return json.load(f)


def write_json(path, data):
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    with open(path, "w") as f:
        json.dump(data, f, indent=1, sort_keys=True)


def clear_data():
    """Remove every object and orphaned datablock of the factory startup file."""
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob, do_unlink=True)
    for coll in (bpy.data.meshes, bpy.data.lights, bpy.data.cameras, bpy.data.materials, bpy.data.images):
        for block in list(coll):
            if block.users == 0:
                coll.remove(block)


def diffuse_material(name, color, roughness=0.0):
    """A material whose surface is a single Diffuse BSDF (Lambertian at roughness 0)."""
    mat = bpy.data.materials.new(name)
    mat.diffuse_color = (color[0], color[1], color[2], 1.0)
    if mat.node_tree is None:
        mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    dif = nt.nodes.new("ShaderNodeBsdfDiffuse")
    dif.inputs["Color"].default_value = (color[0], color[1], color[2], 1.0)
    dif.inputs["Roughness"].default_value = roughness
    nt.links.new(dif.outputs["BSDF"], out.inputs["Surface"])
    return mat


def black_world(scene):
    world = bpy.data.worlds.new("Black")
    world.color = (0.0, 0.0, 0.0)
    if world.node_tree is None:
        world.use_nodes = True
    nodes = world.node_tree.nodes
    bg = next((n for n in nodes if n.type == "BACKGROUND"), None) or nodes.new("ShaderNodeBackground")
    out = next((n for n in nodes if n.type == "OUTPUT_WORLD"), None) or nodes.new("ShaderNodeOutputWorld")
    if not out.inputs["Surface"].is_linked:
        world.node_tree.links.new(bg.outputs["Background"], out.inputs["Surface"])
    bg.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    bg.inputs["Strength"].default_value = 0.0
    scene.world = world


LIGHT_SOURCE_CLASSES = ("lamps", "world", "emission")


def _silence(socket):
    """A shader input to 0, unlinked: what feeds it no longer matters."""
    for link in list(socket.links):
        socket.id_data.links.remove(link)
    socket.default_value = 0.0


def keep_light_sources(scene, sources):
    """Only the light source classes in `sources` ('+'-joined LIGHT_SOURCE_CLASSES) light the scene: the other lamps
    are hidden from the render, the world's Background strength and the materials' emission strength set to 0.
    Geometry stays (a dark emitter still occludes), so each class's render is its share of the whole (the
    benchmark's NAME@SOURCES scenes; tests/blender/test_world_emission.py checks that the shares add up)."""
    keep = set(sources.split("+"))
    if not keep <= set(LIGHT_SOURCE_CLASSES):
        unknown = sorted(keep - set(LIGHT_SOURCE_CLASSES))
        raise ValueError(f"unknown light sources {unknown}; known: {LIGHT_SOURCE_CLASSES}")
    if "lamps" not in keep:
        for ob in scene.objects:
            if ob.type == "LIGHT":
                ob.hide_render = True
    if "world" not in keep and scene.world:
        scene.world.color = (0.0, 0.0, 0.0)
        for node in scene.world.node_tree.nodes if scene.world.use_nodes else []:
            if node.type == "BACKGROUND":
                _silence(node.inputs["Strength"])
    if "emission" not in keep:
        for material in bpy.data.materials:
            for node in material.node_tree.nodes if material.use_nodes else []:
                if node.type == "EMISSION":
                    _silence(node.inputs["Strength"])
                elif node.type == "BSDF_PRINCIPLED":
                    _silence(node.inputs["Emission Strength"])


def add_mesh(scene, name, verts, faces, material=None):
    me = bpy.data.meshes.new(name)
    me.from_pydata(verts, [], faces)
    me.update()
    if material is not None:
        me.materials.append(material)
    ob = bpy.data.objects.new(name, me)
    scene.collection.objects.link(ob)
    return ob


def add_plane(scene, size, z=0.0, material=None, name="Plane"):
    h = size / 2.0
    return add_mesh(scene, name, [(-h, -h, z), (h, -h, z), (h, h, z), (-h, h, z)], [(0, 1, 2, 3)], material)


def add_ortho_camera(scene, center, height, ortho_scale):
    cam = bpy.data.cameras.new("Camera")
    cam.type = "ORTHO"
    cam.ortho_scale = ortho_scale
    cam.clip_start, cam.clip_end = 0.01, 1000.0
    ob = bpy.data.objects.new("Camera", cam)
    ob.location = (center[0], center[1], height)
    ob.rotation_euler = (0.0, 0.0, 0.0)  # looks down -Z, +Y up in the image, +X right
    scene.collection.objects.link(ob)
    scene.camera = ob
    return ob


def set_resolution(scene, w, h):
    r = scene.render
    r.resolution_x, r.resolution_y = w, h
    r.resolution_percentage = 100
    r.pixel_aspect_x = r.pixel_aspect_y = 1.0
    scene.frame_start = scene.frame_end = scene.frame_current = 1


def linear_output(scene):
    """Multilayer float EXR, no view transform (EXR holds scene-linear values anyway)."""
    vs = scene.view_settings
    try:
        vs.view_transform = "Standard"
    except TypeError:
        pass
    vs.look = "None"
    vs.exposure = 0.0
    vs.gamma = 1.0
    s = scene.render.image_settings
    if hasattr(s, "media_type"):  # Blender 5.0+: multilayer EXR is a media type of its own
        s.media_type = "MULTI_LAYER_IMAGE"
    s.file_format = "OPEN_EXR_MULTILAYER"
    s.color_depth = "32"
    s.exr_codec = "ZIP"
    scene.render.use_compositing = False
    scene.render.use_sequencer = False


def single_layer_exr(scene):
    """Plain RGBA EXR of Combined only (no compression)."""
    s = scene.render.image_settings
    if hasattr(s, "media_type"):
        s.media_type = "IMAGE"
    s.file_format = "OPEN_EXR"
    s.color_mode = "RGBA"
    s.color_depth = "32"
    s.exr_codec = "NONE"


def bounce_settings(scene, **values):
    scene.render.engine = "BOUNCE"
    for key, value in values.items():
        setattr(scene.bounce, key, value)


def render_still(scene, path):
    """F12-equivalent: bpy.ops.render.render(write_still=True) into `path` (extension added by Blender)."""
    if bpy.context.window is not None:
        bpy.context.window.scene = scene
    scene.render.filepath = path
    scene.render.use_file_extension = True
    bpy.ops.render.render(write_still=True, scene=scene.name)
    return path + ".exr" if not path.endswith(".exr") else path

