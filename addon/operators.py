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
            return {"FINISHED"}
        window.scene = scene
        view = _view_to_show_in(context, window)
        if view is not None:
            # Seen from outside, the closed box is dark on a black world: look through its camera, rendered.
            view.shading.type = "RENDERED"
            view.region_3d.view_perspective = "CAMERA"
        return {"FINISHED"}


def _view_to_show_in(context, window):
    """The 3D view the operator ran from, else the window's largest: the view a user looks at."""
    if context.space_data is not None and context.space_data.type == "VIEW_3D":
        return context.space_data
    areas = [area for area in window.screen.areas if area.type == "VIEW_3D"]
    if not areas:
        return None
    return max(areas, key=lambda area: area.width * area.height).spaces.active


CLASSES = (BOUNCE_OT_demo_scene, presets.BOUNCE_OT_apply_preset)


def _render_menu_entry(menu, _context):
    menu.layout.separator()
    menu.layout.operator(BOUNCE_OT_demo_scene.bl_idname, icon="SCENE_DATA")


def register_menus():
    bpy.types.TOPBAR_MT_render.append(_render_menu_entry)


def unregister_menus():
    bpy.types.TOPBAR_MT_render.remove(_render_menu_entry)
