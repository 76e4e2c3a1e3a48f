"""The scene's world -> BounceWorld: a uniform radiance, or an equirectangular environment image times a factor,
with the Mapping node's rotation and scale. The world lights the scene (Lights panel: World Directions) and is
seen as the background, unless Film > Transparent is on (colour and alpha 0, as Cycles) or the world's Ray
Visibility > Camera is off (black, alpha 1).

Understood node setups (anything else is warned about and falls back to the world colour):
    [Background | Emission](Color: colour | Environment Texture, Strength)
    Environment Texture(Vector: unlinked | [Mapping(Vector: unlinked | Texture Coordinate Generated)])
"""
import math

from mathutils import Euler, Matrix

from .. import native
from .materials import MISSING_IMAGE_COLOR, NotUnderstood, active_output, upstream, uses_nodes


def convert_world(scene, reports, texture_key):
    """`texture_key(image)`: the native texture of an image (NO_TEXTURE when it has no pixels)."""
    out = native.World()
    out.transparent = 1 if scene.render.film_transparent else 0
    out.world_to_environment[:] = (1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0)
    world = scene.world
    if world is None:
        return out
    # Cycles' Ray Visibility > Camera (the Cycles add-on defines it; Blender without it has no such flag).
    out.camera_hidden = 0 if getattr(getattr(world, "cycles_visibility", None), "camera", True) else 1
    try:
        background, image, mapping = _describe(world)
    except NotUnderstood as reason:
        reports.warn(f"World '{world.name}': {reason}; using the world colour")
        background, image, mapping = tuple(float(c) for c in world.color), None, None
    if image is not None:
        key = texture_key(image)
        if key == native.NO_TEXTURE:
            background = tuple(b * m for b, m in zip(background, MISSING_IMAGE_COLOR))
        else:
            out.environment_texture = key
            if mapping is not None:
                out.world_to_environment[:] = [mapping[row][column] for column in range(3) for row in range(3)]
    out.background[:] = background
    return out


def _describe(world):
    """(factor or radiance, environment image or None, world-to-environment 3x3 Matrix or None)."""
    if not uses_nodes(world):
        return tuple(float(c) for c in world.color), None, None
    output = active_output(world.node_tree, "OUTPUT_WORLD")
    if output is None:
        return (0.0, 0.0, 0.0), None, None
    node, _ = upstream(output.inputs["Surface"])
    if node is None:
        return (0.0, 0.0, 0.0), None, None
    if node.type not in {"BACKGROUND", "EMISSION"}:
        raise NotUnderstood(f"shader '{node.name}' is not supported")
    color, strength = node.inputs["Color"], node.inputs["Strength"]
    if strength.is_linked:
        raise NotUnderstood("a linked Strength is not supported")
    factor = float(strength.default_value)
    source, _ = upstream(color)
    if source is None:
        return tuple(float(c) * factor for c in color.default_value[:3]), None, None
    if source.type != "TEX_ENVIRONMENT":
        raise NotUnderstood(f"colour from node '{source.name}' ({source.bl_label}) is not supported")
    if source.projection != "EQUIRECTANGULAR":
        raise NotUnderstood(f"Environment Texture '{source.name}': only the equirectangular projection is supported")
    if source.image is None:
        return tuple(factor * c for c in MISSING_IMAGE_COLOR), None, None
    return (factor, factor, factor), source.image, _mapping(source.inputs["Vector"])


def _mapping(vector):
    """The world-to-environment matrix of what feeds an Environment Texture's Vector input."""
    node, from_socket = upstream(vector)
    if node is None:
        return None
    if node.type == "TEX_COORD" and from_socket.name == "Generated":
        return None
    if node.type != "MAPPING":
        raise NotUnderstood(f"vector from node '{node.name}' ({node.bl_label}) is not supported")
    source, source_socket = upstream(node.inputs["Vector"])
    if source is not None and not (source.type == "TEX_COORD" and source_socket.name == "Generated"):
        raise NotUnderstood(f"Mapping '{node.name}': only generated coordinates are supported")
    for name in ("Rotation", "Scale"):
        if node.inputs[name].is_linked:
            raise NotUnderstood(f"Mapping '{node.name}': a linked {name} is not supported")
    rotation = Euler(node.inputs["Rotation"].default_value, "XYZ").to_matrix()
    scale = Matrix.Diagonal(node.inputs["Scale"].default_value)
    if node.vector_type in {"POINT", "VECTOR"}:
        return rotation @ scale
    if node.vector_type == "TEXTURE":
        if any(abs(s) < 1e-12 or not math.isfinite(s) for s in node.inputs["Scale"].default_value):
            return None
        return (rotation @ scale).inverted()
    raise NotUnderstood(f"Mapping '{node.name}': type {node.vector_type} is not supported")
