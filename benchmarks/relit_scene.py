"""Builds a benchmark scene lit another way (issue 16: the world and emission against Cycles) or with other
albedos (issue 17: where the bounces matter) from a built base .blend, and saves it as a .blend.

    blender -b --factory-startup --python benchmarks/relit_scene.py -- --base B.blend [--lighting L]
        [--albedo A] --out R.blend

Lightings:
  emissive-panel: every area light becomes a quad of its size and place with an Emission material of its
                  radiance (Cycles: P / (4 A) times the colour for a rectangle; the Cornell box's panel is the OBJ's
                  Ke = (17, 12, 4) again); the lamps are removed, so the emitting surface is the only light.
  hdri:           the lamps are removed; the world is Blender's studio HDRI --hdri (strength 1) through an
                  Environment Texture, so the sky alone lights the scene.
  sky:            the lamps stay and the studio HDRI --hdri is added as the world.
Albedos (every Diffuse BSDF's constant colour):
  white:          0.85 grey everywhere: a bright white room, where the second bounce is most of the indirect light.
  near-black:     the base colour times 0.02 (the Cornell box's white walls 0.015): no bounce matters.
"""
import argparse
import os
import sys

import bpy


def lamps():
    return [o for o in bpy.data.objects if o.type == "LIGHT"]


def remove(objects):
    for obj in objects:
        bpy.data.objects.remove(obj, do_unlink=True)


def emissive_panels(scene):
    for lamp in lamps():
        light = lamp.data
        if light.type != "AREA" or light.shape not in ("RECTANGLE", "SQUARE"):
            sys.exit(f"relit_scene: light '{lamp.name}' is not a rectangular area light")
        sx = light.size
        sy = light.size_y if light.shape == "RECTANGLE" else light.size
        radiance = light.energy / (4.0 * sx * sy)
        material = bpy.data.materials.new(f"{lamp.name} emission")
        material.use_nodes = True
        nodes = material.node_tree.nodes
        nodes.clear()
        emission = nodes.new("ShaderNodeEmission")
        emission.inputs["Color"].default_value = (*light.color, 1.0)
        emission.inputs["Strength"].default_value = radiance
        output = nodes.new("ShaderNodeOutputMaterial")
        material.node_tree.links.new(emission.outputs["Emission"], output.inputs["Surface"])
        mesh = bpy.data.meshes.new(f"{lamp.name} panel")
        h = (sx / 2.0, sy / 2.0)
        mesh.from_pydata([(-h[0], -h[1], 0.0), (h[0], -h[1], 0.0), (h[0], h[1], 0.0), (-h[0], h[1], 0.0)], [],
                         [(0, 3, 2, 1)])  # facing -Z, as the lamp shines
        mesh.materials.append(material)
        panel = bpy.data.objects.new(f"{lamp.name} panel", mesh)
        panel.matrix_world = lamp.matrix_world.copy()
        scene.collection.objects.link(panel)
        print(f"panel {sx:.3f} x {sy:.3f} m, radiance {radiance:.4f} x {tuple(round(c, 4) for c in light.color)}")
    remove(lamps())


def hdri_world(scene, name):
    path = os.path.join(bpy.utils.system_resource("DATAFILES", path="studiolights"), "world", name)
    world = bpy.data.worlds.new(f"Studio {name}")
    world.use_nodes = True
    nodes, links = world.node_tree.nodes, world.node_tree.links
    nodes.clear()
    background = nodes.new("ShaderNodeBackground")
    environment = nodes.new("ShaderNodeTexEnvironment")
    environment.image = bpy.data.images.load(path)
    links.new(environment.outputs["Color"], background.inputs["Color"])
    links.new(background.outputs["Background"], nodes.new("ShaderNodeOutputWorld").inputs["Surface"])
    scene.world = world
    print(f"world: {path}")


ALBEDOS = {"white": lambda colour: (0.85, 0.85, 0.85), "near-black": lambda colour: tuple(0.02 * c for c in colour)}


def set_albedo(name):
    recolour = ALBEDOS[name]
    for material in bpy.data.materials:
        for node in material.node_tree.nodes if material.use_nodes else []:
            if node.type != "BSDF_DIFFUSE":
                continue
            colour = node.inputs["Color"]
            if colour.is_linked:
                sys.exit(f"relit_scene: material '{material.name}' has a textured colour; --albedo needs constants")
            colour.default_value = (*recolour(colour.default_value[:3]), 1.0)
            print(f"{material.name}: albedo {tuple(round(c, 4) for c in colour.default_value[:3])}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--base", required=True)
    parser.add_argument("--base-key", help="the base scene's cache key (rebuilds this one when it changes)")
    parser.add_argument("--lighting", choices=["emissive-panel", "hdri", "sky"])
    parser.add_argument("--albedo", choices=sorted(ALBEDOS))
    parser.add_argument("--hdri", default="courtyard.exr")
    parser.add_argument("--out", required=True)
    args = parser.parse_args(sys.argv[sys.argv.index("--") + 1:])
    bpy.ops.wm.open_mainfile(filepath=os.path.abspath(args.base))
    scene = bpy.context.scene
    if args.lighting == "emissive-panel":
        emissive_panels(scene)
    elif args.lighting:
        if args.lighting == "hdri":
            remove(lamps())
        hdri_world(scene, args.hdri)
    if args.albedo:
        set_albedo(args.albedo)
    bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(args.out), compress=False)


main()
