"""The Blender-level scene fuzzer (issue 18): random scenes built through bpy and rendered F12-style by the add-on,
in one Blender, so that what the native fuzzer cannot reach (the add-on's export of meshes, materials, lights,
the world and settings) meets hard input too.

    blender -b --factory-startup --python fuzz_scenes.py -- SEED FIRST COUNT OUT_DIR

Case i of seed s is always the same scene (Python's random.Random(s * 1000003 + i)): a camera (perspective or
orthographic, anywhere, sometimes inside an object), up to four meshes (mostly scene-sized triangles, a few
coordinates NaN, infinite or huge, objects scaled from 1e-6 to 1e6) and in most cases a ground plane, materials
with random base colour, emission (strength up to 1e30), cut-outs and missing textures, up to three lights of
every type with powers from {0, -100, 1e-20, normal, 1e30, 3.4e38, NaN} and sizes from 0, a world of random
colour and strength or an HDRI (Blender's studio lights) or a missing one, and every scene.bounce setting drawn
from its soft range (a few capped, CAPS, so that a case stays within seconds on two cores); a fifth of the lights
cast no shadow, and a third of the cases get a plain sun from above that casts none. Each case writes
OUT_DIR/case-I.exr (multilayer, every pass) when Blender wrote an image, and appends one JSON line to
OUT_DIR/cases.jsonl: {"case", "seed", "method", "render_error" (the message bpy.ops.render.render raised, or
null), "exr", "unshadowed_suns" (each sun that casts no shadow: the direction towards it, energy, colour)}. "case
I start" is printed before each case, so that a crash names the case it died in; the pytest side (test_fuzz.py)
checks the images.
"""
import json
import math
import os
import random
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bl_common as bc  # noqa: E402

RES = (32, 24)
HARD_VALUES = (float("nan"), float("inf"), 3.4e38, 1e30, 1e10, 1e9, 1e-30, 0.0)
POWERS = (0.0, -100.0, 1e-20, None, 1e30, 3.4e38, float("nan"))  # None: a normal power
# Settings whose soft maximum makes a case take minutes on two cores; the rest span their whole soft range.
CAPS = {"samples": 2, "topology_resolution": 64, "topology_vpls": 1024, "shadow_map_size": 2048,
        "tile_size": 1024, "world_lights": 8, "emission_lights": 16}


def coordinate(rng, extent):
    if rng.random() >= 0.03:
        return rng.uniform(-extent, extent)
    return rng.choice((-1.0, 1.0)) * rng.choice(HARD_VALUES)


def missing_image(name, path):
    image = bpy.data.images.new(name, 4, 4)
    image.source = "FILE"
    image.filepath = path
    return image


def power(rng, normal):
    value = rng.choice(POWERS) if rng.random() < 0.5 else None
    return normal if value is None else value


def studio_hdri():
    folder = bpy.utils.system_resource("DATAFILES", path=os.path.join("studiolights", "world"))
    names = sorted(n for n in os.listdir(folder) if n.endswith(".exr")) if folder and os.path.isdir(folder) else []
    return [os.path.join(folder, n) for n in names]


def random_material(rng, index):
    mat = bpy.data.materials.new(f"Fuzz{index}")
    mat.use_nodes = True
    nt = mat.node_tree
    bsdf = next(n for n in nt.nodes if n.type == "BSDF_PRINCIPLED")
    bsdf.inputs["Base Color"].default_value = (rng.random(), rng.random(), rng.random(), 1.0)
    if rng.random() < 0.3:
        emission = "Emission Color" if "Emission Color" in bsdf.inputs else "Emission"
        bsdf.inputs[emission].default_value = (rng.random(), rng.random(), rng.random(), 1.0)
        if "Emission Strength" in bsdf.inputs:
            bsdf.inputs["Emission Strength"].default_value = rng.choice((0.0, 1.0, 10.0, 1e6, 1e30))
    if rng.random() < 0.15:
        tex = nt.nodes.new("ShaderNodeTexImage")
        if rng.random() < 0.5:
            tex.image = missing_image(f"FuzzMissing{index}", "/nonexistent/bounce-fuzz-missing.png")
        else:
            image = bpy.data.images.new(f"FuzzTex{index}", 4, 4, alpha=True)
            image.pixels = [rng.random() for _ in range(64)]
            tex.image = image
        nt.links.new(tex.outputs["Color"], bsdf.inputs["Base Color"])
        if rng.random() < 0.5:
            nt.links.new(tex.outputs["Alpha"], bsdf.inputs["Alpha"])
            if hasattr(mat, "blend_method"):
                mat.blend_method = "CLIP"
    return mat


def random_mesh(rng, scene, index):
    extent = rng.choice((0.5, 2.0, 5.0))
    count = rng.randint(1, 40)
    verts = [(coordinate(rng, extent), coordinate(rng, extent), coordinate(rng, extent)) for _ in range(3 * count)]
    faces = [(3 * t, 3 * t + 1, 3 * t + 2) for t in range(count)]
    ob = bc.add_mesh(scene, f"Fuzz{index}", verts, faces, random_material(rng, index))
    ob.location = [rng.uniform(-3.0, 3.0) for _ in range(3)]
    ob.rotation_euler = [rng.uniform(-math.pi, math.pi) for _ in range(3)]
    ob.scale = [rng.choice((1.0, 1.0, 1.0, 1e-6, 1e6, -1.0, 0.0))] * 3
    return ob


def random_light(rng, scene, index):
    kind = rng.choice(("POINT", "SPOT", "SUN", "AREA"))
    light = bpy.data.lights.new(f"FuzzLight{index}", type=kind)
    light.energy = power(rng, rng.uniform(1.0, 1000.0) if kind != "SUN" else rng.uniform(0.1, 10.0))
    light.color = (rng.random(), rng.random(), rng.random())
    if kind in ("POINT", "SPOT"):
        light.shadow_soft_size = rng.choice((0.0, 0.1, 1.0, 100.0))
    if kind == "SPOT":
        light.spot_size = rng.uniform(0.01, math.pi)
        light.spot_blend = rng.random()
    if kind == "SUN":
        light.angle = rng.uniform(0.0, 3.0)
    if kind == "AREA":
        light.shape = rng.choice(("SQUARE", "RECTANGLE", "DISK", "ELLIPSE"))
        light.size = rng.choice((0.0, 0.1, 1.0, 1e6))
        light.size_y = rng.choice((0.0, 0.5, 2.0))
    set_casts_shadow(light, rng.random() < 0.8)
    ob = bpy.data.objects.new(f"FuzzLight{index}", light)
    ob.location = [coordinate(rng, 6.0) for _ in range(3)]
    ob.rotation_euler = [rng.uniform(-math.pi, math.pi) for _ in range(3)]
    scene.collection.objects.link(ob)
    return ob


def set_casts_shadow(light, value):
    owner, name = bc.addon_module("export.lights").shadow_property(light)
    if owner is not None:
        setattr(owner, name, value)


def casts_shadow(light):
    return bc.addon_module("export.lights").casts_shadow(light)


def unshadowed_suns(scene):
    """[(unit direction towards the sun, energy, colour)] of the suns that cast no shadow: the pytest side's
    silent-black-frame check."""
    bpy.context.view_layer.update()
    suns = []
    for ob in scene.objects:
        if ob.type == "LIGHT" and ob.data.type == "SUN" and not casts_shadow(ob.data):
            towards = ob.matrix_world.to_3x3().col[2].normalized()
            suns.append(([towards.x, towards.y, towards.z], ob.data.energy, list(ob.data.color)))
    return suns


def random_camera(rng, scene):
    cam = bpy.data.cameras.new("FuzzCamera")
    if rng.random() < 0.2:
        cam.type = "ORTHO"
        cam.ortho_scale = rng.choice((1e-4, 1.0, 10.0, 1e4))
    else:
        cam.lens = rng.uniform(5.0, 200.0)
    cam.clip_start = rng.choice((1e-4, 0.01, 0.1, 1.0))
    cam.clip_end = rng.choice((10.0, 100.0, 1e6))
    ob = bpy.data.objects.new("FuzzCamera", cam)
    ob.location = [rng.uniform(-10.0, 10.0) for _ in range(3)]
    # Looks at the origin most of the time, anywhere otherwise.
    if rng.random() < 0.9:
        direction = -ob.location.copy()
        if direction.length > 0.0:
            ob.rotation_euler = direction.to_track_quat("-Z", "Y").to_euler()
    else:
        ob.rotation_euler = [rng.uniform(-math.pi, math.pi) for _ in range(3)]
    scene.collection.objects.link(ob)
    scene.camera = ob


def random_world(rng, scene, hdris):
    bc.black_world(scene)
    nodes = scene.world.node_tree.nodes
    background = next(n for n in nodes if n.type == "BACKGROUND")
    background.inputs["Color"].default_value = (rng.random(), rng.random(), rng.random(), 1.0)
    background.inputs["Strength"].default_value = rng.choice((0.0, 0.0, 1.0, 5.0, 1e6, float("nan")))
    if rng.random() < 0.2:
        tex = nodes.new("ShaderNodeTexEnvironment")
        if hdris and rng.random() < 0.7:
            tex.image = bpy.data.images.load(rng.choice(hdris), check_existing=True)
        else:
            tex.image = missing_image("FuzzMissingSky", "/nonexistent/bounce-fuzz-sky.exr")
        scene.world.node_tree.links.new(tex.outputs["Color"], background.inputs["Color"])
    scene.render.film_transparent = rng.random() < 0.2


def random_settings(rng, scene):
    settings = scene.bounce
    for prop in settings.bl_rna.properties:
        name = prop.identifier
        if name == "rna_type" or prop.is_readonly:
            continue
        if prop.type == "ENUM":
            setattr(settings, name, rng.choice([item.identifier for item in prop.enum_items]))
        elif prop.type == "BOOLEAN":
            setattr(settings, name, rng.random() < 0.5)
        elif prop.type == "INT":
            setattr(settings, name, rng.randint(prop.soft_min, min(prop.soft_max, CAPS.get(name, prop.soft_max))))
        elif prop.type == "FLOAT":
            setattr(settings, name, rng.uniform(prop.soft_min, min(prop.soft_max, CAPS.get(name, prop.soft_max))))


def build_case(seed, index, hdris):
    rng = random.Random(seed * 1000003 + index)
    bc.clear_data()
    for worlds in list(bpy.data.worlds):
        bpy.data.worlds.remove(worlds)
    scene = bpy.context.scene
    bc.set_resolution(scene, *RES)
    bc.linear_output(scene)
    scene.render.engine = "BOUNCE"
    random_world(rng, scene, hdris)
    random_camera(rng, scene)
    if rng.random() < 0.6:  # a ground under the origin, so that most cases show lit surfaces
        bc.add_plane(scene, 20.0, z=-1.0, material=random_material(rng, 99), name="FuzzGround")
    for i in range(rng.randint(0, 4)):
        random_mesh(rng, scene, i)
    for i in range(rng.randint(0, 3)):
        random_light(rng, scene, i)
    if rng.random() < 0.3:  # a plain sun from above, casting no shadow: what the silent-black-frame rule judges
        sun = bpy.data.lights.new("FuzzSun", type="SUN")
        sun.energy = rng.uniform(0.5, 10.0)
        set_casts_shadow(sun, False)
        ob = bpy.data.objects.new("FuzzSun", sun)
        ob.rotation_euler = (rng.uniform(-1.2, 1.2), rng.uniform(-1.2, 1.2), 0.0)
        scene.collection.objects.link(ob)
    random_settings(rng, scene)
    return scene


def main():
    seed, first, count, out = int(bc.args()[0]), int(bc.args()[1]), int(bc.args()[2]), bc.args()[3]
    os.makedirs(out, exist_ok=True)
    hdris = studio_hdri()
    for index in range(first, first + count):
        print(f"case {index} start", flush=True)
        scene = build_case(seed, index, hdris)
        path = os.path.join(out, f"case-{index}")
        error = None
        try:
            bc.render_still(scene, path)
        except RuntimeError as e:  # a refused render: Blender raises with the engine's report
            error = str(e)
        exr = path + ".exr"
        with open(os.path.join(out, "cases.jsonl"), "a") as f:
            f.write(json.dumps({"case": index, "seed": seed, "render_error": error,
                                "exr": exr if os.path.isfile(exr) else None,
                                "method": scene.bounce.method, "unshadowed_suns": unshadowed_suns(scene)}) + "\n")
        print(f"case {index} done", flush=True)


main()
