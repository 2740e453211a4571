"""The terrain mesh, in world space, handed to the engine as a heightfield."""

import numpy as np

from . import WorldPaintError, engine, geometry, scene_maps


def mesh_arrays(obj, depsgraph):
    """World-space vertices float64 (N, 3) and triangles uint32 (M, 3) of the evaluated mesh object."""
    return mesh_with_maps(obj, depsgraph)[:2]


def mesh_with_maps(obj, depsgraph, vertex_maps=()):
    """``mesh_arrays`` and the values per vertex of the mesh's ``vertex_maps`` (scene map names), {name: float64
    (N,)}."""
    evaluated = obj.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    try:
        world = geometry.vertices_world(obj, mesh)
        mesh.calc_loop_triangles()
        tris = np.empty(len(mesh.loop_triangles) * 3, dtype=np.int32)
        mesh.loop_triangles.foreach_get("vertices", tris)
        values = {name: scene_maps.vertex_values(obj, mesh, name) for name in vertex_maps}
    finally:
        evaluated.to_mesh_clear()
    return world, tris.reshape(-1, 3).astype(np.uint32), values


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


def optional_terrain_object(context, name=""):
    """The terrain object as ``terrain_object`` finds it, or None when none is named or picked (flat ground)."""
    if not name and context.scene.worldpaint.terrain is None:
        return None
    return terrain_object(context, name)


def engine_terrain(context, obj, maps=()):
    """The engine's Terrain of a mesh object, with the scene maps (``scene_maps`` names) among ``maps``."""
    depsgraph = context.evaluated_depsgraph_get()
    wanted = [name for name in maps if scene_maps.is_scene_map(name)]
    by_vertex = [name for name in wanted if scene_maps.split(name)[0] in scene_maps.VERTEX_PREFIXES]
    vertices, triangles, values = mesh_with_maps(obj, depsgraph, by_vertex)
    if len(triangles) == 0:
        raise WorldPaintError(f"The terrain '{obj.name}' has no faces")
    heightfield = engine.terrain(vertices, triangles)
    try:
        for name in wanted:
            if name in values:
                heightfield = heightfield.with_vertex_map(name, vertices, triangles, values[name])
            else:
                geometry_xy = scene_maps.distance_geometry(depsgraph, name, exclude={obj})
                heightfield = heightfield.with_distance_map(name, *geometry_xy)
    except engine.engine_error() as exc:
        raise WorldPaintError(f"The map '{name}' on the terrain '{obj.name}': {exc}") from exc
    return heightfield


def check_region_on_terrain(terrain, region, what):
    """A clear error when the region does not overlap the terrain at all."""
    (tx0, ty0), (tx1, ty1) = terrain.bbox()
    (rx0, ry0), (rx1, ry1) = engine.region_bbox(region)
    if rx1 <= tx0 or rx0 >= tx1 or ry1 <= ty0 or ry0 >= ty1:
        raise WorldPaintError(
            f"The {what} region ({rx0:.1f}..{rx1:.1f}, {ry0:.1f}..{ry1:.1f}) lies outside the terrain "
            f"({tx0:.1f}..{tx1:.1f}, {ty0:.1f}..{ty1:.1f})"
        )
