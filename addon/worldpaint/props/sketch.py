"""Scene data of the sketch (thesis ch. 5): the silhouette strokes drawn over a camera's view, and how Apply Sketch
deforms the terrain to them.

Strokes live on ``scene.worldpaint.sketch.strokes``, each point in the camera frame's normalized coordinates (x from 0
at the left to 1 at the right, y from 0 at the bottom to 1 at the top, as ``world_to_camera_view`` gives them), so
they are saved in the .blend and read the same whatever the viewport's size.
"""

import bpy

SOURCES = (
    ("STROKES", "Strokes", "The strokes drawn with the Sketch Silhouettes tool"),
    ("ANNOTATION", "Annotation", "The strokes of an annotation layer, seen through the camera"),
)


class WORLDPAINT_PG_sketch_point(bpy.types.PropertyGroup):
    """A point of a silhouette stroke in the camera frame (0-1 in x and y)."""

    co: bpy.props.FloatVectorProperty(name="Point", size=2)


class WORLDPAINT_PG_sketch_stroke(bpy.types.PropertyGroup):
    """A silhouette stroke, and where Apply Sketch put it in depth."""

    points: bpy.props.CollectionProperty(type=WORLDPAINT_PG_sketch_point)
    depth_rank: bpy.props.IntProperty(
        name="Depth", default=-1, min=-1,
        description="Place of the stroke from front (0) to back found by the last Apply Sketch (-1: not applied yet)",
    )


class WORLDPAINT_PG_sketch(bpy.types.PropertyGroup):
    """The sketch and how the terrain is deformed to it."""

    camera: bpy.props.PointerProperty(
        name="Camera", type=bpy.types.Object,
        description="Camera the strokes are drawn through (empty: the scene camera)",
    )
    strokes: bpy.props.CollectionProperty(type=WORLDPAINT_PG_sketch_stroke)
    source: bpy.props.EnumProperty(name="Strokes From", items=SOURCES, default="STROKES")
    annotation_layer: bpy.props.StringProperty(
        name="Layer", description="Annotation layer whose strokes are read through the camera (empty: the active one)",
    )
    reach: bpy.props.FloatProperty(
        name="Reach", default=0.0, min=0.0, soft_max=2000.0, unit='LENGTH',
        description="Distance from the sketched silhouettes beyond which the terrain stays as it was (0: eight times "
                    "the largest height change, at most half the distance from the camera to the nearest silhouette)",
    )
    completion: bpy.props.BoolProperty(
        name="Complete to Ground", default=True,
        description="Extend each silhouette along its ends until it meets the terrain, so that seen from elsewhere it "
                    "does not begin in mid-air",
    )
    show_features: bpy.props.BoolProperty(
        name="Show Features", default=True,
        description="Draw the detected terrain features and the matched ones as curves in a 'Sketch' collection",
    )
    reseat: bpy.props.BoolProperty(
        name="Re-seat", default=True,
        description="Move instances and village houses standing on changed ground with it",
    )
