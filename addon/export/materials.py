"""Blender materials -> the diffuse + emission + cut-out surface Bounce renders.

Understood node setups, walked back from the active Material Output's Surface input:
  - Principled BSDF: Base Color, Alpha, Emission ("Emission" in 3.x, "Emission Color" in 4.x) x Emission Strength
  - Diffuse BSDF: Color
  - Emission: Color x Strength (no diffuse reflection)
  (an emission colour is read as a base colour is, image texture included; a strength must be a constant)
  - Mix Shader of a Transparent BSDF (first input) and one of the above, whose Fac is an Image Texture's Alpha,
    directly or through a Math "Greater Than" node (the cut-out that shared/scenes/setups/common.py makes)
  - colours: a constant, an RGB node, an Image Texture's Color, or a Multiply mix of a texture and a constant
    (as glTF imports make); an image texture's Alpha into the Principled Alpha makes a cut-out.
Anything else falls back to DEFAULT_COLOR and is reported once per sync. A Surface with nothing linked renders
black, as in Cycles. Materials without nodes use their viewport colour (diffuse_color).
"""
from dataclasses import dataclass
from typing import Optional

import bpy

DEFAULT_COLOR = (0.8, 0.8, 0.8)       # Blender's default surface
MISSING_IMAGE_COLOR = (1.0, 0.0, 1.0)  # what Cycles draws for a missing image
DEFAULT_ALPHA_THRESHOLD = 0.5


@dataclass
class SurfaceDesc:
    base_color: tuple = DEFAULT_COLOR
    alpha: float = 1.0
    image: Optional[object] = None    # bpy.types.Image whose colour multiplies base_color
    alpha_from_texture: bool = False  # the image's alpha is a cut-out
    alpha_threshold: Optional[float] = None  # None: the material's own (alpha clip) threshold
    emission: tuple = (0.0, 0.0, 0.0)
    emission_image: Optional[object] = None  # bpy.types.Image whose colour multiplies emission


class NotUnderstood(Exception):
    """A node setup outside the list above; the message says what."""


def describe_material(material, reports):
    """The SurfaceDesc of a (evaluated) material; None gives the default surface."""
    if material is None:
        return SurfaceDesc()
    if not uses_nodes(material):
        return SurfaceDesc(base_color=_rgb(material.diffuse_color))
    try:
        return _describe_node_tree(material)
    except NotUnderstood as reason:
        reports.warn(f"Material '{material.name}': {reason}; rendered as diffuse grey {DEFAULT_COLOR[0]}")
        return SurfaceDesc()


def uses_nodes(datablock):
    """Whether a material or world is defined by its node tree (always from 5.0, which deprecates use_nodes)."""
    if datablock.node_tree is None:
        return False
    return bpy.app.version >= (5, 0, 0) or datablock.use_nodes


def _describe_node_tree(material):
    output = active_output(material.node_tree, "OUTPUT_MATERIAL")
    if output is None:
        raise NotUnderstood("no Material Output node")
    surface_node, _ = upstream(output.inputs["Surface"])
    if surface_node is None:
        return SurfaceDesc(base_color=(0.0, 0.0, 0.0))
    desc = _describe_shader(surface_node)
    if desc.alpha_threshold is None:
        desc.alpha_threshold = float(getattr(material, "alpha_threshold", DEFAULT_ALPHA_THRESHOLD))
    return desc


def _describe_shader(node):
    kind = node.type
    if kind == "BSDF_PRINCIPLED":
        return _principled(node)
    if kind == "BSDF_DIFFUSE":
        color, image = _color_source(node.inputs["Color"])
        return SurfaceDesc(base_color=color, image=image)
    if kind == "EMISSION":
        emission, emission_image = _emission(node.inputs["Color"], node.inputs["Strength"])
        return SurfaceDesc(base_color=(0.0, 0.0, 0.0), emission=emission, emission_image=emission_image)
    if kind == "MIX_SHADER":
        return _mix_shader(node)
    raise NotUnderstood(f"shader node '{node.name}' ({node.bl_label}) is not supported")


def _principled(node):
    color, image = _color_source(node.inputs["Base Color"])
    emission_color = node.inputs.get("Emission Color") or node.inputs.get("Emission")  # 4.x name, 3.x name
    emission, emission_image = _emission(emission_color, node.inputs.get("Emission Strength"))
    desc = SurfaceDesc(base_color=color, image=image, emission=emission, emission_image=emission_image)
    alpha_input = node.inputs["Alpha"]
    if alpha_input.is_linked:
        _set_cutout(desc, alpha_input)
    else:
        desc.alpha = float(alpha_input.default_value)
    return desc


def _mix_shader(node):
    fac, first, second = node.inputs[0], node.inputs[1], node.inputs[2]
    first_node, _ = upstream(first)
    second_node, _ = upstream(second)
    if not fac.is_linked and fac.default_value in (0.0, 1.0):
        chosen = first_node if fac.default_value == 0.0 else second_node
        return _describe_shader(chosen) if chosen is not None else SurfaceDesc(base_color=(0.0, 0.0, 0.0))
    if first_node is None or first_node.type != "BSDF_TRANSPARENT" or second_node is None:
        raise NotUnderstood(f"Mix Shader '{node.name}' is not a Transparent BSDF cut-out")
    desc = _describe_shader(second_node)
    _set_cutout(desc, fac)
    return desc


def _set_cutout(desc, socket):
    """Make `desc` a cut-out by the texture alpha that feeds `socket`, directly or through alpha > threshold
    steps: the core reads alpha from the base-colour texture and compares it with the threshold.

    A step of a 0/1 step is the same step when its threshold is in [0, 1): Blender 4.2+ inserts such a Math
    node when it versions alpha-clip materials (blend mode CLIP was removed), so chains of them are walked and
    the innermost threshold is the one that counts."""
    threshold = None
    node, _ = upstream(socket)
    while node is not None and node.type == "MATH" and node.operation == "GREATER_THAN" \
            and not node.inputs[1].is_linked and not getattr(node, "use_clamp", False):
        if threshold is not None and not 0.0 <= threshold < 1.0:
            raise NotUnderstood(f"Math node '{node.name}' is followed by a step at {threshold}, not in [0, 1)")
        threshold = float(node.inputs[1].default_value)
        socket = node.inputs[0]
        node, _ = upstream(socket)
    alpha_image = _texture_alpha(socket)
    if desc.image is None or desc.image.original != alpha_image.original:
        raise NotUnderstood("the cut-out alpha comes from another image than the base colour")
    desc.alpha_from_texture = True
    if threshold is not None:
        desc.alpha_threshold = threshold


def _texture_alpha(socket):
    """The image whose Alpha output feeds `socket`."""
    node, from_socket = upstream(socket)
    if node is None or node.type != "TEX_IMAGE" or from_socket.name != "Alpha":
        raise NotUnderstood(f"input '{socket.name}' is not an Image Texture's Alpha")
    if node.image is None:
        raise NotUnderstood(f"Image Texture '{node.name}' has no image")
    return node.image


def _color_source(socket):
    """(constant colour, image or None) whose product is the colour fed into `socket`."""
    if not socket.is_linked:
        return _rgb(socket.default_value), None
    node, from_socket = upstream(socket)
    if node is None:
        return _rgb(socket.default_value), None
    if node.type == "TEX_IMAGE" and from_socket.name == "Color":
        if node.image is None:
            return MISSING_IMAGE_COLOR, None
        return (1.0, 1.0, 1.0), node.image
    if node.type == "RGB":
        return _rgb(node.outputs[0].default_value), None
    factors = _multiply_inputs(node)
    if factors is not None:
        (color_a, image_a), (color_b, image_b) = (_color_source(s) for s in factors)
        if image_a is not None and image_b is not None:
            raise NotUnderstood(f"'{node.name}' multiplies two images")
        return tuple(a * b for a, b in zip(color_a, color_b)), image_a or image_b
    raise NotUnderstood(f"colour from node '{node.name}' ({node.bl_label}) is not supported")


def _multiply_inputs(node):
    """The two colour inputs of a Multiply mix at full factor (legacy MixRGB, or 3.4+'s Mix in colour mode)."""
    if node.type == "MIX_RGB":
        fac, a, b = node.inputs["Fac"], node.inputs["Color1"], node.inputs["Color2"]
    elif node.type == "MIX" and getattr(node, "data_type", "") == "RGBA":
        fac, a, b = node.inputs[0], node.inputs[6], node.inputs[7]
    else:
        return None
    if node.blend_type != "MULTIPLY" or fac.is_linked or fac.default_value != 1.0:
        return None
    return a, b


def _emission(color_socket, strength_socket):
    """(emitted radiance, image or None whose colour multiplies it): the colour as base colours are read."""
    if color_socket is None:
        return (0.0, 0.0, 0.0), None
    strength = 1.0
    if strength_socket is not None:
        if strength_socket.is_linked:
            raise NotUnderstood("a linked emission strength is not supported")
        strength = float(strength_socket.default_value)
    if strength == 0.0:
        return (0.0, 0.0, 0.0), None
    color, image = _color_source(color_socket)
    return tuple(c * strength for c in color), image


def upstream(socket):
    """(node, output socket) linked into `socket`, through reroutes; (None, None) when nothing is."""
    while socket.is_linked:
        link = socket.links[0]
        if getattr(link, "is_muted", False) or not link.is_valid:
            return None, None
        node = link.from_node
        if node.type == "REROUTE":
            socket = node.inputs[0]
            continue
        if node.mute:
            raise NotUnderstood(f"node '{node.name}' is muted")
        return node, link.from_socket
    return None, None


def active_output(node_tree, output_type):
    outputs = [n for n in node_tree.nodes if n.type == output_type]
    active = [n for n in outputs if n.is_active_output]
    return (active or outputs or [None])[0]


def _rgb(color):
    return (float(color[0]), float(color[1]), float(color[2]))
