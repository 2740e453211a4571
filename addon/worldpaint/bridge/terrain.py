"""The terrain mesh, in world space, handed to the engine as a heightfield."""

import numpy as np

from . import WorldPaintError, engine, geometry


def mesh_arrays(obj, depsgraph):
    """World-space vertices float64 (N, 3) and triangles uint32 (M, 3) of the evaluated mesh object."""
    evaluated = obj.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    try:
        world = geometry.vertices_world(obj, mesh)
        mesh.calc_loop_triangles()
        tris = np.empty(len(mesh.loop_triangles) * 3, dtype=np.int32)
        mesh.loop_triangles.foreach_get("vertices", tris)
    finally:
        evaluated.to_mesh_clear()
    return world, tris.reshape(-1, 3).astype(np.uint32)


def terrain_object(context, name=""):
    """The terrain object: the named one, else the scene's WorldPaint terrain; a clear error when there is none."""
    settings = context.scene.worldpaint
    obj = context.scene.objects.get(name) if name else settings.terrain
    if name and obj is None:
        raise WorldPaintError(f"No object named '{name}' in the scene to use as terrain")
    if obj is None:
        raise WorldPaintError("No terrain: pick the terrain mesh in the WorldPaint panel")
    if obj.type != 'MESH':
        raise WorldPaintError(f"The terrain '{obj.name}' is not a mesh")
    return obj


def engine_terrain(context, obj):
    """The engine's Terrain of a mesh object."""
    vertices, triangles = mesh_arrays(obj, context.evaluated_depsgraph_get())
    if len(triangles) == 0:
        raise WorldPaintError(f"The terrain '{obj.name}' has no faces")
    return engine.terrain(vertices, triangles)


def check_region_on_terrain(terrain, region, what):
    """A clear error when the region does not overlap the terrain at all."""
    (tx0, ty0), (tx1, ty1) = terrain.bbox()
    (rx0, ry0), (rx1, ry1) = engine.region_bbox(region)
    if rx1 <= tx0 or rx0 >= tx1 or ry1 <= ty0 or ry0 >= ty1:
        raise WorldPaintError(
            f"The {what} region ({rx0:.1f}..{rx1:.1f}, {ry0:.1f}..{ry1:.1f}) lies outside the terrain "
            f"({tx0:.1f}..{tx1:.1f}, {ty0:.1f}..{ty1:.1f})"
        )
