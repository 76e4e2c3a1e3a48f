"""Files saved by older Bounce versions: settings that were renamed or merged keep their values when the file opens.

Blender keeps a removed property's value in the file as a raw ID property of `scene.bounce`; a `load_post` handler
moves it into the setting that replaced it and deletes the raw key.
"""
import bpy


def _merge_topology_bounces(group):
    """`topology_bounces` (before API 4) became the common `bounces`. A file that stored both keeps the one its method
    read; a file that never changed `bounces` (Blender stores no value at the default) takes the topology's."""
    old = group.get("topology_bounces")
    if old is None:
        return
    if "bounces" not in group.keys() or group.method == "TOPOLOGY":
        group.bounces = int(old)  # RNA clamps it to the setting's range
    del group["topology_bounces"]


_MIGRATIONS = (_merge_topology_bounces,)


def migrate(scene):
    group = getattr(scene, "bounce", None)
    if group is None:
        return
    for migration in _MIGRATIONS:
        migration(group)


@bpy.app.handlers.persistent
def _on_load(*_args):  # Blender 3.x passes a scene, 4.x the file path
    for scene in bpy.data.scenes:
        migrate(scene)


def register():
    if _on_load not in bpy.app.handlers.load_post:
        bpy.app.handlers.load_post.append(_on_load)


def unregister():
    if _on_load in bpy.app.handlers.load_post:
        bpy.app.handlers.load_post.remove(_on_load)
