"""The viewport side of the brushes: where the mouse points on the terrain, and the brush circle drawn on it."""

import math

import gpu
from bpy_extras import view3d_utils
from gpu_extras.batch import batch_for_shader
from mathutils import Vector

CIRCLE_SEGMENTS = 48
CURSOR_COLOR = (1.0, 1.0, 1.0, 0.9)
CURSOR_WIDTH = 2.0  # pixels


def mouse_ray(context, coord):
    """(origin, direction) in world space of the view ray through the region pixel ``coord``."""
    region, rv3d = context.region, context.region_data
    origin = view3d_utils.region_2d_to_origin_3d(region, rv3d, coord)
    direction = view3d_utils.region_2d_to_vector_3d(region, rv3d, coord)
    return origin, direction


def ray_to_terrain(terrain_obj, origin, direction):
    """World location where a world-space ray meets the terrain object, or None."""
    inverse = terrain_obj.matrix_world.inverted()
    local_origin = inverse @ origin
    local_direction = (inverse.to_3x3() @ direction).normalized()
    hit, location, _normal, _index = terrain_obj.ray_cast(local_origin, local_direction)
    return terrain_obj.matrix_world @ location if hit else None


def terrain_under_mouse(context, terrain_obj, event):
    """World location of the terrain under the mouse, or None (also outside a 3D viewport)."""
    if context.region is None or context.region_data is None:
        return None
    origin, direction = mouse_ray(context, (event.mouse_region_x, event.mouse_region_y))
    return ray_to_terrain(terrain_obj, origin, direction)


def ground_circle(terrain_obj, center, radius):
    """Points of a circle of ``radius`` around ``center`` laid on the terrain (vertical rays from above it)."""
    top = max((terrain_obj.matrix_world @ Vector(c)).z for c in terrain_obj.bound_box) + 1.0
    points = []
    for k in range(CIRCLE_SEGMENTS):
        a = 2.0 * math.pi * k / CIRCLE_SEGMENTS
        x, y = center.x + radius * math.cos(a), center.y + radius * math.sin(a)
        hit = ray_to_terrain(terrain_obj, Vector((x, y, top)), Vector((0.0, 0.0, -1.0)))
        points.append(hit if hit is not None else Vector((x, y, center.z)))
    return points


def draw_brush_circle(context, terrain_obj, xy, radius):
    """Draws the brush circle on the terrain under the region pixel ``xy`` (a tool's cursor callback)."""
    region = context.region
    if terrain_obj is None or region is None or context.region_data is None or radius <= 0.0:
        return
    origin, direction = mouse_ray(context, xy)
    center = ray_to_terrain(terrain_obj, origin, direction)
    if center is None:
        return
    pixels = []
    for p in ground_circle(terrain_obj, center, radius):
        q = view3d_utils.location_3d_to_region_2d(region, context.region_data, p)
        if q is not None:
            pixels.append((q.x, q.y))
    draw_line_loop(pixels, (region.width, region.height), CURSOR_COLOR, CURSOR_WIDTH)


def draw_line_loop(pixels, viewport_size, color, width):
    """Draws a closed line through region pixels, ``width`` pixels wide. The polyline shader draws wide lines on
    every GPU backend (OpenGL, Metal, Vulkan), where a line width set on the GPU state works on OpenGL alone."""
    if len(pixels) < 3:
        return
    shader = gpu.shader.from_builtin('POLYLINE_UNIFORM_COLOR')
    batch = batch_for_shader(shader, 'LINE_LOOP', {"pos": [(x, y, 0.0) for x, y in pixels]})
    gpu.state.blend_set('ALPHA')
    shader.uniform_float("viewportSize", viewport_size)
    shader.uniform_float("lineWidth", width)
    shader.uniform_float("color", color)
    batch.draw(shader)
    gpu.state.blend_set('NONE')


def draw_segments(points, color, width):
    """Draws world-space line segments (pairs of consecutive XYZ ``points``) over everything in the viewport,
    ``width`` pixels wide (see ``draw_line_loop`` on the shader)."""
    shader = gpu.shader.from_builtin('POLYLINE_UNIFORM_COLOR')
    batch = batch_for_shader(shader, 'LINES', {"pos": [tuple(p) for p in points]})
    viewport = gpu.state.viewport_get()
    shader.uniform_float("viewportSize", (viewport[2], viewport[3]))
    shader.uniform_float("lineWidth", width)
    shader.uniform_float("color", color)
    gpu.state.depth_test_set('NONE')
    batch.draw(shader)
