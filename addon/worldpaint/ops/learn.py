"""Learn Color: the statistics of the selected example objects and curves become a new color in the palette."""

import bpy
from bpy.props import BoolProperty, StringProperty

from ..bridge import WorldPaintError, curves, engine, instances, regions, terrain
from .background import with_progress
from .colors import add_palette_color, fidelity_view, unique_name
from .common import RegionProperties, TerrainProperty, reports_errors


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

    oriented: StringProperty(
        name="Oriented Pairs",
        description="Pairs 'category:other', comma-separated, whose relation also depends on direction (an oriented "
        "rdf: houses facing a road, grass downhill of rocks)",
    )

    def oriented_pairs(self, categories):
        """The oriented pairs as (category, other), checked against the categories."""
        kinds = {c["name"]: c["kind"] for c in categories}
        pairs = []
        for item in filter(None, (part.strip() for part in self.oriented.split(","))):
            pair = tuple(name.strip() for name in item.split(":"))
            if len(pair) != 2 or not all(pair):
                raise WorldPaintError(f"Oriented pair '{item}' is not of the form 'category:other'")
            unknown = [name for name in pair if name not in kinds]
            if unknown:
                raise WorldPaintError(f"Oriented pair '{item}': no category {', '.join(unknown)} in the example")
            structured = [name for name in pair if kinds[name] in ("graph", "polygon")]
            if structured:
                raise WorldPaintError(f"Oriented pair '{item}': {', '.join(structured)} is a graph or polygon, "
                                      "seen through its distance; oriented pairs are between distributions")
            pairs.append(pair)
        return pairs

    @reports_errors
    def execute(self, context):
        scene = context.scene
        settings = scene.worldpaint
        terrain_obj = terrain.terrain_object(context, self.terrain)
        mode = self.resolved_region_mode(context)
        region_curve = regions.find_curve(context, self.curve) if mode == 'CURVE' else None
        examples = instances.example_objects(context.selected_objects, exclude=[terrain_obj])
        drawn = curves.example_curves(context.selected_objects, exclude=[terrain_obj, region_curve])
        if not examples and not drawn:
            raise WorldPaintError(
                "Nothing to learn: select the example objects (collection instances, linked duplicates or "
                "objects with a 'wp_category' property) and curves (roads, rivers; closed: islands, lakes)"
            )
        # merged silently, two things of one name would be learned as one and pasted as either
        instances.check_example_categories(examples, drawn)
        # the region is around the example objects; curves (which usually run on beyond it) only when alone
        region = regions.region_for(
            context,
            mode,
            objects=[obj for obj, _ in examples] or [obj for obj, _, _ in drawn],
            use_bounds=not examples,
            **self.region_kwargs(),
        )
        heightfield = terrain.engine_terrain(context, terrain_obj)
        terrain.check_region_on_terrain(heightfield, region, "example")

        new = instances.new_categories(settings, examples, drawn)
        categories = instances.merged_categories(settings, new)
        exemplar = instances.example_set(examples, categories)
        structures = curves.StructureSet(categories=categories)
        for obj, category, _ in drawn:
            structures.add(obj, category, locked=True)
        # a typed name the palette has is numbered, as the Pipette and Interpolate Colors do
        name = unique_name(settings.palette, self.name or "Color")
        maps = ["slope", "elevation"] if self.use_elevation else ["slope"]
        scene_data = engine.scene(heightfield, exemplar.engine_arrays(), structures.engine_arrays())
        color_json = engine.learn_color(scene_data, region, name, maps, self.oriented_pairs(categories))
        # the color painted into its own example region and learned back: how well it reproduces the example
        fidelity = with_progress(context, lambda progress: fidelity_view(color_json, heightfield, progress))

        # validated and computed: now change the scene
        instances.add_categories(settings, new)
        entry = add_palette_color(settings, name, color_json, fidelity)
        n_categories = len({c for _, c in examples} | {c for _, c, _ in drawn})
        self.report({'INFO'}, f"Learned '{name}' from {len(exemplar)} instances and {len(structures)} curves in "
                              f"{n_categories} categories; painted into its example's region: {entry.fidelity_line()}")
        return {'FINISHED'}
