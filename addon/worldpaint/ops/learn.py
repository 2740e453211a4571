"""Learn Color: the statistics of the selected example objects become a new color in the palette."""

import bpy
from bpy.props import BoolProperty, StringProperty

from ..bridge import WorldPaintError, instances, regions, terrain
from ..bridge.engine import engine
from .colors import add_palette_color, unique_name
from .common import RegionProperties, TerrainProperty, report_errors


class WORLDPAINT_OT_learn_color(RegionProperties, TerrainProperty, bpy.types.Operator):
    """Learn the arrangement of the selected example objects as a new palette color"""

    bl_idname = "worldpaint.learn_color"
    bl_label = "Learn Color"
    bl_options = {'REGISTER', 'UNDO'}

    name: StringProperty(name="Name", description="Name of the new color (empty: Color N)")
    use_elevation: BoolProperty(
        name="Height Preference",
        default=False,
        description="Also learn which terrain heights the example occupies (the slope preference is always learned); "
        "heights beyond the example's range are treated like its highest or lowest ones",
    )

    def execute(self, context):
        return report_errors(self, lambda: self._learn(context))

    def _learn(self, context):
        scene = context.scene
        settings = scene.worldpaint
        terrain_obj = terrain.terrain_object(context, self.terrain)
        examples = instances.example_objects(context.selected_objects, exclude=[terrain_obj])
        if not examples:
            raise WorldPaintError(
                "Nothing to learn: select the example objects (collection instances, linked duplicates or "
                "objects with a 'wp_category' property)"
            )
        region = regions.region_for(
            context,
            self.resolved_region_mode(context),
            objects=[obj for obj, _ in examples],
            use_bounds=False,
            **self.region_kwargs(),
        )
        heightfield = terrain.engine_terrain(context, terrain_obj)
        terrain.check_region_on_terrain(heightfield, region, "example")

        # new categories enter the priority order rarest first: few large things (trees, rocks) condition the many
        counts = {}
        for _, category in examples:
            counts[category] = counts.get(category, 0) + 1
        new_names = sorted(instances.missing_categories(settings, counts), key=lambda c: (counts[c], c))
        base = max((c.priority for c in settings.categories), default=-1) + 1
        new = [
            {"name": n, "layer": "default", "kind": "distribution", "priority": base + i}
            for i, n in enumerate(new_names)
        ]
        categories = instances.merged_categories(settings, new)
        exemplar = instances.example_set(examples, categories)
        name = self.name or unique_name(settings.palette, "Color")
        maps = ["slope", "elevation"] if self.use_elevation else ["slope"]
        eng = engine()
        color_json = eng.learn_color(eng.Scene(heightfield, **exemplar.engine_arrays()), region, name,
                                     options={"maps": maps})

        # validated and computed: now change the scene
        for category in new:
            item = settings.categories.add()
            item.name, item.layer, item.kind, item.priority = (
                category["name"], category["layer"], category["kind"], category["priority"],
            )
        add_palette_color(settings, name, color_json)
        self.report({'INFO'}, f"Learned '{name}' from {len(exemplar)} instances in {len(counts)} categories")
        return {'FINISHED'}

