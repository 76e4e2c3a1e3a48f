"""The scene's world -> BounceWorld (a constant background radiance)."""
from .. import native
from .materials import uses_nodes


def convert_world(scene, reports):
    out = native.World()
    out.transparent = 1 if scene.render.film_transparent else 0
    out.background[:] = _background(scene.world, reports)
    return out


def _background(world, reports):
    if world is None:
        return (0.0, 0.0, 0.0)
    if not uses_nodes(world):
        return tuple(float(c) for c in world.color)
    outputs = [n for n in world.node_tree.nodes if n.type == "OUTPUT_WORLD"]
    output = next((n for n in outputs if n.is_active_output), outputs[0] if outputs else None)
    if output is None or not output.inputs["Surface"].is_linked:
        return (0.0, 0.0, 0.0)
    node = output.inputs["Surface"].links[0].from_node
    while node.type == "REROUTE" and node.inputs[0].is_linked:
        node = node.inputs[0].links[0].from_node
    if node.type not in {"BACKGROUND", "EMISSION"}:
        reports.warn(f"World '{world.name}': shader '{node.name}' is not supported; using the world colour")
        return tuple(float(c) for c in world.color)
    color, strength = node.inputs["Color"], node.inputs["Strength"]
    if color.is_linked or strength.is_linked:
        reports.warn(f"World '{world.name}': a textured background is not supported; using the world colour")
        return tuple(float(c) for c in world.color)
    return tuple(float(c) * float(strength.default_value) for c in color.default_value[:3])
