"""Bounce's operators."""
import bpy

from . import demo, presets


class BOUNCE_OT_demo_scene(bpy.types.Operator):
    """Create a new scene with the Cornell box, lit by an area light, set to render with Bounce"""

    bl_idname = "bounce.demo_scene"
    bl_label = "Bounce Demo: Cornell Box"
    bl_options = {"REGISTER", "UNDO"}

    resolution: bpy.props.IntProperty(name="Resolution", description="Width and height of the image in pixels",
                                      default=256, min=1, soft_max=2048, subtype="PIXEL")

    def execute(self, context):
        scene = bpy.data.scenes.new(demo.SCENE_NAME)
        demo.build(scene, self.resolution)
        window = context.window or next(iter(context.window_manager.windows), None)
        if window is None:
            self.report({"WARNING"}, f"Created scene '{scene.name}'; no window to show it in")
        else:
            window.scene = scene
        return {"FINISHED"}


CLASSES = (BOUNCE_OT_demo_scene, presets.BOUNCE_OT_apply_preset)


def _render_menu_entry(menu, _context):
    menu.layout.separator()
    menu.layout.operator(BOUNCE_OT_demo_scene.bl_idname, icon="SCENE_DATA")


def register_menus():
    bpy.types.TOPBAR_MT_render.append(_render_menu_entry)


def unregister_menus():
    bpy.types.TOPBAR_MT_render.remove(_render_menu_entry)
