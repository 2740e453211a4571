"""The only place that converts between bpy and the engine.

``terrain`` extracts the terrain mesh, ``instances`` the example objects and synthesized points, ``curves`` the roads,
rivers, islands and lakes (and builds their ribbons and filled meshes), ``regions`` the analysed or destination
region, ``files`` the file paths the user gives, ``points`` builds the point clouds and the Geometry Nodes instancer,
``preview`` the palette pictures, ``village`` the villages' surroundings and the generated villages, ``place`` an
imported real place (terrain, building and tree clouds, road and area curves, its frame), ``sketch`` the
sketch camera and the shown features, ``sketch_strokes`` the sketched strokes in the camera frame (drawn or read from
annotations) and the viewport's pixels in that frame, ``view`` the brush circle on the terrain. ``geometry``
reads meshes and curves in world space (the one way a curve is sampled), ``engine`` is the one typed facade over the
compiled engine and ``compat`` the one place that knows how Blender's versions differ.
"""


class WorldPaintError(Exception):
    """A problem with the user's input, reported in Blender's UI; nothing has been changed when it is raised."""
