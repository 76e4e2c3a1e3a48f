"""Small hand-built scenes for robustness and pass tests: build case CASE, render it F12-style with Bounce
(bpy.ops.render.render(write_still=True), multilayer 32-bit EXR), record what happened.

    blender -b --factory-startup --python scene_case.py -- CASE OUT_DIR

Writes OUT_DIR/CASE.exr (when Blender wrote an image) and OUT_DIR/CASE.json: {"render_error": message of the
exception bpy.ops.render.render raised, or null; "exr": path or null; ...}. A render that fails with an error
report is not a script failure: the pytest side decides what each case expects.
"""
import math
import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bl_common as bc  # noqa: E402

RES = 32


def base(scene, camera=True, light=True, ground=True):
    """Ground plane, a perspective camera looking at the origin from above, a 1000 W point light."""
    if ground:
        bc.add_plane(scene, 10.0, material=bc.diffuse_material("Ground", (0.8, 0.8, 0.8)), name="Ground")
    if camera:
        cam = bpy.data.cameras.new("Camera")
        cam.lens = 35.0
        ob = bpy.data.objects.new("Camera", cam)
        ob.location = (0.0, -6.0, 4.0)
        ob.rotation_euler = (math.radians(56.3), 0.0, 0.0)
        scene.collection.objects.link(ob)
        scene.camera = ob
    if light:
        add_point_light(scene, 1000.0, (1.0, -1.0, 4.0))


def add_point_light(scene, energy, location, name="Light"):
    ld = bpy.data.lights.new(name, type="POINT")
    ld.energy = energy
    ld.shadow_soft_size = 0.1
    ob = bpy.data.objects.new(name, ld)
    ob.location = location
    scene.collection.objects.link(ob)
    return ob


def cube_mesh(scene, name, size, location, material=None):
    h = size / 2.0
    verts = [(x, y, z) for x in (-h, h) for y in (-h, h) for z in (-h, h)]
    faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    ob = bc.add_mesh(scene, name, verts, faces, material)
    ob.location = location
    return ob


# ---- cases ------------------------------------------------------------------------------------------------

def case_nan_vertices(scene):
    base(scene)
    ob = cube_mesh(scene, "NaNCube", 1.0, (0.0, 0.0, 0.5))
    co = [0.0] * (len(ob.data.vertices) * 3)
    ob.data.vertices.foreach_get("co", co)
    co[0] = float("nan")
    co[4] = float("inf")
    co[8] = float("-inf")
    ob.data.vertices.foreach_set("co", co)
    ob.data.update()


def case_degenerate_triangles(scene):
    base(scene)
    verts = [(0, 0, 1), (1, 0, 1), (1, 0, 1),            # zero area: two equal vertices
             (0, 1, 1), (1, 1, 1), (2, 1, 1),            # collinear
             (0, 2, 1), (0, 2, 1), (0, 2, 1),            # a point
             (-1, -1, 0.5), (-0.5, -1, 0.5), (-1, -0.5, 0.5)]  # one good triangle
    bc.add_mesh(scene, "Degenerate", verts, [(0, 1, 2), (3, 4, 5), (6, 7, 8), (9, 10, 11)])


def case_tiny_triangles(scene):
    base(scene)
    e = 1e-20  # area ~1e-40: below float precision, not exactly zero
    verts = [(0, 0, 1), (e, 0, 1), (0, e, 1), (1e20, 0, 1), (1e20, 1, 1), (1e20, 0, 2)]
    bc.add_mesh(scene, "Tiny", verts, [(0, 1, 2), (3, 4, 5)])


def case_empty_scene(scene):
    pass  # no objects at all: no camera either


def case_camera_only(scene):
    base(scene, light=False, ground=False)


def case_no_faces(scene):
    base(scene)
    bc.add_mesh(scene, "Wire", [(0, 0, 1), (1, 0, 1), (1, 1, 1)], [])
    me = bpy.data.meshes.new("Edges")
    me.from_pydata([(0, 0, 1), (1, 0, 1), (1, 1, 1)], [(0, 1), (1, 2)], [])
    scene.collection.objects.link(bpy.data.objects.new("Edges", me))
    scene.collection.objects.link(bpy.data.objects.new("NoVerts", bpy.data.meshes.new("NoVerts")))


def case_light_0w(scene):
    base(scene, light=False)
    add_point_light(scene, 0.0, (1.0, -1.0, 4.0))


def case_light_1e9w(scene):
    base(scene, light=False)
    add_point_light(scene, 1e9, (1.0, -1.0, 4.0))


def case_light_nan(scene):
    base(scene, light=False)
    ob = add_point_light(scene, 100.0, (1.0, -1.0, 4.0))
    ob.data["energy"] = float("nan")  # IDProperty path around the RNA range check
    ob.data.energy = float("nan")


def case_camera_inside_object(scene):
    base(scene)
    cube_mesh(scene, "Shell", 2.0, (0.0, -6.0, 4.0), bc.diffuse_material("Shell", (0.5, 0.5, 0.5)))


def case_missing_texture(scene):
    base(scene)
    mat = bc.diffuse_material("Textured", (0.8, 0.8, 0.8))
    nt = mat.node_tree
    img = bpy.data.images.new("missing", 4, 4)
    img.source = "FILE"
    img.filepath = "/nonexistent/bounce-missing-texture.png"
    tex = nt.nodes.new("ShaderNodeTexImage")
    tex.image = img
    dif = next(n for n in nt.nodes if n.type == "BSDF_DIFFUSE")
    nt.links.new(tex.outputs["Color"], dif.inputs["Color"])
    cube_mesh(scene, "TexturedCube", 1.5, (0.0, 0.0, 0.75), mat)


def case_resolution_1x1(scene):
    base(scene)
    cube_mesh(scene, "Cube", 1.0, (0.0, 0.0, 0.5))
    bc.set_resolution(scene, 1, 1)


def case_resolution_large(scene):
    base(scene)
    cube_mesh(scene, "Cube", 1.0, (0.0, 0.0, 0.5))
    size = int(os.environ.get("BOUNCE_TEST_LARGE_RES", "8192"))
    bc.set_resolution(scene, size, size)
    scene.bounce.samples = 1
    # only Combined: a 17-channel 32-bit EXR of 8192^2 would take minutes to compress and GBs to hold
    bc.single_layer_exr(scene)


def case_far_geometry(scene):
    """A triangle 1e20 m away in a mesh, an object moved 1e20 m away; hard shadow-mapped shadows of a point light
    (the far bounds used to zero Direct light everywhere)."""
    base(scene)
    cube_mesh(scene, "Cube", 1.0, (0.0, 0.0, 0.5))
    bc.add_mesh(scene, "FarTriangle", [(0, 0, 1), (1, 0, 1), (0, 1, 1), (1e20, 0, 1), (1e20, 1, 1), (1e20, 0, 2)],
                [(0, 1, 2), (3, 4, 5)])
    cube_mesh(scene, "FarCube", 1.0, (0.0, 1e20, 0.0))
    scene.bounce.shadow_method = "SHADOW_MAPS"
    scene.bounce.shadow_softness = 0.0


def case_far_light(scene):
    """A point light 1e19 m away beside the usual one (Topology traced its VPL paths from there)."""
    base(scene)
    cube_mesh(scene, "Cube", 1.0, (0.0, 0.0, 0.5))
    add_point_light(scene, 1000.0, (1e19, 0.0, 4.0), name="FarLight")


def case_ortho_scale_zero(scene):
    base(scene)
    cube_mesh(scene, "Cube", 1.0, (0.0, 0.0, 0.5))
    scene.camera.data.type = "ORTHO"
    scene.camera.data.ortho_scale = 0.0  # Blender's camera matrix is then all zeros (3.4, 4.3)
    projection = scene.camera.calc_matrix_camera(bpy.context.evaluated_depsgraph_get(),
                                                 x=scene.render.resolution_x, y=scene.render.resolution_y)
    if projection.determinant() != 0.0:  # 5.2 keeps the matrix regular
        print("Blender's camera matrix at ortho_scale 0 is regular")


def case_invalid_settings(scene):
    base(scene)
    cube_mesh(scene, "Cube", 1.0, (0.0, 0.0, 0.5))
    # RNA clamps out-of-range assignments; the ID-property path (old files, drivers, scripts) does not.
    scene.bounce.samples = 0
    print("samples after RNA assignment of 0:", scene.bounce.samples)
    scene.bounce["samples"] = 0
    scene.bounce["shadow_map_size"] = 3
    scene.bounce["filter_width"] = float("nan")
    print("raw settings:", dict(scene.bounce.items()))


def case_invalid_enum(scene):
    base(scene)
    cube_mesh(scene, "Cube", 1.0, (0.0, 0.0, 0.5))
    scene.bounce["method"] = 99
    print("method after raw assignment of 99:", repr(scene.bounce.method))


def case_emission(scene):
    """Passes: an emissive quad (Emission shader, colour (1, 0.5, 0.25), strength 2) beside a lit cube."""
    base(scene)
    scene.bounce.filter_width = 0.0  # pixel centres: no partly covered pixels at the quad's edges
    cube_mesh(scene, "Cube", 1.0, (1.0, 0.0, 0.5))
    mat = bpy.data.materials.new("Glow")
    if mat.node_tree is None:
        mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    em = nt.nodes.new("ShaderNodeEmission")
    em.inputs["Color"].default_value = (1.0, 0.5, 0.25, 1.0)
    em.inputs["Strength"].default_value = 2.0
    nt.links.new(em.outputs["Emission"], out.inputs["Surface"])
    glow = bc.add_mesh(scene, "Glow", [(-2, -1, 0.01), (-0.5, -1, 0.01), (-0.5, 0.5, 0.01), (-2, 0.5, 0.01)],
                       [(0, 1, 2, 3)], mat)
    glow.location = (0, 0, 0.02)


def environment_world(scene, image):
    """The black world's Background fed by an Environment Texture of `image` (strength 1)."""
    nodes, links = scene.world.node_tree.nodes, scene.world.node_tree.links
    background = next(n for n in nodes if n.type == "BACKGROUND")
    background.inputs["Strength"].default_value = 1.0
    environment = nodes.new("ShaderNodeTexEnvironment")
    environment.image = image
    links.new(environment.outputs["Color"], background.inputs["Color"])


def float_image(name, width, height, rgba):
    image = bpy.data.images.new(name, width, height, float_buffer=True)
    image.pixels.foreach_set(rgba)
    return image


def case_hdri_sun_pixel(scene):
    """A sky of radiance 0.1 with one texel of 1e6 (64 x 32, 45 degrees up): the ground is lit by a sun."""
    base(scene, light=False)
    rgba = [0.1, 0.1, 0.1, 1.0] * (64 * 32)
    rgba[(24 * 64 + 10) * 4:(24 * 64 + 10) * 4 + 3] = [1e6] * 3
    environment_world(scene, float_image("sun_pixel", 64, 32, rgba))


def case_environment_1x1(scene):
    """A 1 x 1 environment of (0.5, 0.25, 1): a uniform sky; the open ground reflects 0.8 of it. The world's Ray
    Visibility > Camera is off: the camera sees black beyond the ground."""
    base(scene, light=False)
    scene.bounce.samples = 64  # 256 world directions
    environment_world(scene, float_image("one_texel", 1, 1, [0.5, 0.25, 1.0, 1.0]))
    scene.world.cycles_visibility.camera = False


def case_missing_environment(scene):
    """An Environment Texture whose file is missing: magenta, as Cycles, and reported."""
    base(scene, light=False)
    scene.bounce.samples = 64
    image = bpy.data.images.new("missing_sky", 4, 4)
    image.source = "FILE"
    image.filepath = "/nonexistent/bounce-missing-sky.exr"
    environment_world(scene, image)


def case_emitter_1e9(scene):
    """A black world; an emissive quad of strength 1e9 above the ground, in one mesh with two zero-area faces."""
    base(scene, light=False)
    mat = bpy.data.materials.new("Blinding")
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    emission = nt.nodes.new("ShaderNodeEmission")
    emission.inputs["Strength"].default_value = 1e9
    nt.links.new(emission.outputs["Emission"], nt.nodes.new("ShaderNodeOutputMaterial").inputs["Surface"])
    bc.add_mesh(scene, "Blinding",
                [(-0.5, -0.5, 1.0), (0.5, -0.5, 1.0), (0.5, 0.5, 1.0), (-0.5, 0.5, 1.0), (1, 1, 1), (2, 1, 1),
                 (3, 1, 1)], [(0, 3, 2, 1), (4, 5, 6), (4, 4, 5)], mat)


def room(scene, albedo):
    """Auto: a closed 4 m room of grey `albedo` lit by a 100 W point light under its ceiling, seen from inside."""
    base(scene, ground=False, light=False)
    cube_mesh(scene, "Room", 4.0, (0.0, 0.0, 2.0), bc.diffuse_material("Walls", (albedo, albedo, albedo)))
    add_point_light(scene, 100.0, (0.5, 0.5, 3.5))
    camera = scene.camera
    camera.location = (0.0, -1.8, 1.5)
    camera.rotation_euler = (math.radians(80.0), 0.0, 0.0)


def case_auto_white_room(scene):
    """Each bounce adds 0.8 of the last: both bounces are simulated."""
    room(scene, 0.8)


def case_auto_grey_room(scene):
    """Albedo 0.05: the first bounce is about 7 % of the image, the second under 1 %: one bounce."""
    room(scene, 0.05)


def case_auto_black_room(scene):
    """Albedo 0.005: bounces add 0.5 %, below the 1 % threshold: direct light only."""
    room(scene, 0.005)


def case_auto_time_limit(scene):
    """The white room with more samples than 2 seconds hold: Time Limit stops the render."""
    room(scene, 0.8)
    scene.bounce.samples = 65536
    scene.bounce.time_limit = 2.0


def case_auto_dim_world(scene):
    """The lit ground under a sky of radiance 1e-4: the world gives far less than 1 % and is left out."""
    base(scene)
    background = next(n for n in scene.world.node_tree.nodes if n.type == "BACKGROUND")
    background.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    background.inputs["Strength"].default_value = 1e-4


def main():
    case, out = bc.args()[:2]
    method = bc.args()[2] if len(bc.args()) > 2 else "DIRECT"
    os.makedirs(out, exist_ok=True)
    bc.clear_data()
    scene = bpy.context.scene
    bc.black_world(scene)
    bc.set_resolution(scene, RES, RES)
    bc.linear_output(scene)
    bc.bounce_settings(scene, method=method, samples=4, shadow_map_size=256)
    globals()["case_" + case](scene)
    path = os.path.join(out, case)
    error = None
    try:
        bc.render_still(scene, path)
    except RuntimeError as e:  # Blender raises for errors it reports itself (e.g. no camera)
        error = str(e)
        print(f"render raised: {error}")
    exr = path + ".exr"
    bc.write_json(os.path.join(out, case + ".json"), {
        "render_error": error, "exr": exr if os.path.isfile(exr) else None,
        "resolution": [scene.render.resolution_x, scene.render.resolution_y]})
    print(f"case {case} done")


main()
