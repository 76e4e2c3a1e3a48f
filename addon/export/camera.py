"""Cameras -> BounceCamera: the scene camera for final renders, the region's view for the viewport."""
from .. import native


class CameraError(Exception):
    """The scene cannot be rendered from a camera (none set, zero resolution)."""


def render_size(render):
    """Full image size in pixels: resolution x percentage, as Blender computes it."""
    scale = render.resolution_percentage / 100.0
    return max(1, int(render.resolution_x * scale)), max(1, int(render.resolution_y * scale))


def border_crop(render, width, height):
    """(x0, y0, x1, y1) of the render border in pixels (bottom-left origin), or None for the whole image.
    Truncates like Blender does, so the size matches the RenderResult Blender makes."""
    if not render.use_border:
        return None
    x0, x1 = int(render.border_min_x * width), int(render.border_max_x * width)
    y0, y1 = int(render.border_min_y * height), int(render.border_max_y * height)
    if x1 - x0 < 1 or y1 - y0 < 1 or (x0, y0, x1, y1) == (0, 0, width, height):
        return None
    return x0, y0, x1, y1


def final_camera(engine, depsgraph):
    scene = depsgraph.scene
    render = scene.render
    camera_object = engine.camera_override or scene.camera
    if camera_object is None:
        raise CameraError("The scene has no camera")
    camera_object = camera_object.evaluated_get(depsgraph)
    width, height = render_size(render)
    # calc_matrix_camera covers perspective/orthographic/panoramic fallbacks, sensor fit, shift and clipping.
    projection = camera_object.calc_matrix_camera(depsgraph, x=width, y=height,
                                                  scale_x=render.pixel_aspect_x, scale_y=render.pixel_aspect_y)
    world_to_view = camera_object.matrix_world.normalized().inverted_safe()
    return make_camera(world_to_view, projection, width, height, border_crop(render, width, height),
                       scene.frame_current)


def viewport_camera(context):
    region, view = context.region, context.region_data
    return make_camera(view.view_matrix, view.window_matrix, region.width, region.height, None,
                       context.scene.frame_current)


def make_camera(world_to_view, projection, width, height, crop, frame):
    camera = native.Camera()
    camera.world_to_view[:] = column_major(world_to_view)
    camera.projection[:] = column_major(projection)
    camera.width, camera.height = int(width), int(height)
    camera.crop[:] = crop or (0, 0, 0, 0)
    camera.frame = int(frame)
    return camera


def column_major(matrix):
    """16 floats of a 4x4 mathutils matrix, column after column (OpenGL order)."""
    return tuple(float(matrix[row][col]) for col in range(4) for row in range(4))
