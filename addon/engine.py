"""The RenderEngine Blender sees. Each method hands over to final.py or viewport.py."""
import bpy

from . import final, session, viewport


class BounceRenderEngine(bpy.types.RenderEngine):
    bl_idname = "BOUNCE"
    bl_label = "Bounce"
    bl_use_preview = True
    bl_use_shading_nodes_custom = False  # keep Blender's shader nodes: materials are read from them
    bl_use_eevee_viewport = True         # Material Preview shading stays EEVEE

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)  # required from Blender 4.4

    def __del__(self):
        # Blender's data of this engine is gone already: only the module-level session may be touched.
        try:
            session.release(id(self))
        except Exception:  # interpreter shutdown: modules may be half torn down
            pass
        parent_del = getattr(super(), "__del__", None)
        if parent_del is not None:
            parent_del()

    def render(self, depsgraph):
        final.render(self, depsgraph)

    def view_update(self, context, depsgraph):
        viewport.view_update(self, context, depsgraph)

    def view_draw(self, context, depsgraph):
        viewport.view_draw(self, context, depsgraph)

    def update_render_passes(self, scene=None, renderlayer=None):
        final.register_passes(self, scene, renderlayer)

    @property
    def bounce_stats(self):
        """SyncStats of this engine's scene sync (None before the first sync)."""
        current = session.find(self)
        return current.scene.stats if current is not None else None
