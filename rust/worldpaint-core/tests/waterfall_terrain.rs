//! Waterfall scenes, the terrain part (thesis 4.4): the riverbed under the water and the banks beside it, the
//! falloff, the overhangs, the decoration maps, the rocks synthesized from a rock color and determinism. Run with
//! `cargo test -p worldpaint-core --release --test waterfall_terrain -- --nocapture` to see the figures.

use glam::{DVec2, DVec3};
use worldpaint_core::{
    build_waterfall_scene, distance_transform, hard_core_points, learn_color, river_rock_color,
    river_rocks, scene_from_points, village_terrain, waterfall_controllers, AnalysisOptions,
    Controller, ControllerKind, Heightfield, Interaction, Region, Rock, WaterPart, WaterfallParams,
    WaterfallScene, WaterfallSceneOptions, WaterfallType, RIVER_ROCK_CATEGORY, RIVER_ROCK_DENSITY,
    RIVER_ROCK_SPACING, ROCK_MAP,
};

fn setup() -> (Heightfield, Vec<Controller>) {
    let t = village_terrain(1000.0, 2.0, 3);
    let c = waterfall_controllers(&t, 20, 7);
    (t, c)
}

fn made(
    t: &Heightfield,
    c: &[Controller],
    options: &WaterfallSceneOptions,
    seed: u64,
) -> WaterfallScene {
    match build_waterfall_scene(t, c, &WaterfallParams::default(), options, seed) {
        Ok(s) => s,
        Err(e) => panic!("the test scene: {e}"),
    }
}

/// The test terrain and its scene with the default options, seed 1.
fn default_scene() -> (Heightfield, WaterfallScene) {
    let (t, c) = setup();
    let s = made(&t, &c, &WaterfallSceneOptions::default(), 1);
    (t, s)
}

fn height(t: &Heightfield, p: DVec2) -> f64 {
    t.height_at(p).unwrap_or(f64::NAN)
}

/// How close to the water's level a bank counts as back at it (m).
const STRICT_BANK: f64 = 0.1;

#[test]
fn riverbed_below_the_water_and_banks_beside_it() {
    let (t, s) = default_scene();
    println!("report: {:?}", s.report);
    let h = &s.terrain.terrain;
    let (mut checked, mut below, mut banks_ok, mut banks_strict) = (0, 0, 0, 0);
    let (mut worst_below, mut worst_bank) = (f64::NEG_INFINITY, f64::INFINITY);
    for (k, seg) in s.network.segments.iter().enumerate() {
        if seg.kind != ControllerKind::Contact {
            continue;
        }
        let (a, b) = (seg.points[0], seg.points[seg.points.len() - 1]);
        let m = a.lerp(b, 0.5);
        // only where this segment's own water is over the midpoint (not under a pool or another river)
        let Some(node) = s.maps.node(m.truncate()) else {
            continue;
        };
        if s.maps.water[node] < 0.5 {
            continue;
        }
        let hw = s
            .mesh
            .part
            .iter()
            .zip(&s.mesh.element)
            .position(|(p, e)| *p == WaterPart::Contact && *e == k)
            .map(|v| s.mesh.vertices[v].distance(s.mesh.vertices[v + 1]))
            .unwrap_or(0.0);
        let along = (b - a).truncate().normalize_or_zero();
        let side = along.perp();
        checked += 1;
        let depth = m.z - height(h, m.truncate());
        worst_below = worst_below.max(-depth);
        if depth > 0.0 {
            below += 1;
        }
        // one cell beyond each bank the ground is back at the water's level, unless other water lies there
        let (mut ok, mut ok_strict) = (true, true);
        for sign in [-1.0, 1.0] {
            let q = m.truncate() + side * sign * (hw + t.cell);
            if s.maps.is_water(q) {
                continue;
            }
            let rise = height(h, q) - m.z;
            worst_bank = worst_bank.min(rise);
            // the bank nodes take the level of the water nearest to them, which in a bend of a steep stream can
            // lie a little downstream: within half a metre counts as back at the water
            ok &= rise >= -0.5;
            ok_strict &= rise >= -STRICT_BANK;
        }
        if ok {
            banks_ok += 1;
        }
        if ok_strict {
            banks_strict += 1;
        }
        if k < 3 {
            println!("segment {k}: half-width {hw:.2} m, water depth at the axis {depth:.2} m");
        }
    }
    println!(
        "contact segments checked {checked}: riverbed below the surface at {below}, banks back within 0.5 m of the water level at {banks_ok}, within {:.2} m at {banks_strict}; worst axis {worst_below:.3} m above the surface, lowest bank {worst_bank:.3} m relative to the surface",
        STRICT_BANK
    );
    // the water over the ground all along the ribbons: their axis vertices (the flowing water) over the carved
    // terrain, also where a stream is narrower than a grid cell
    let mesh = &s.mesh;
    let axis: Vec<f64> = (0..mesh.vertices.len())
        .filter(|&v| mesh.part[v] == WaterPart::Contact && mesh.speed[v].length() > 0.0)
        .map(|v| mesh.vertices[v].z - height(h, mesh.vertices[v].truncate()))
        .filter(|d| d.is_finite())
        .collect();
    let over = axis.iter().filter(|d| **d > 0.0).count();
    println!(
        "ribbon axis vertices over the ground: {over} of {}, lowest {:.2} m",
        axis.len(),
        axis.iter().copied().fold(f64::INFINITY, f64::min)
    );
    assert!(
        over as f64 >= 0.98 * axis.len() as f64,
        "water under the ground at {} axis vertices",
        axis.len() - over
    );
    assert!(checked > 100, "only {checked} contact segments checked");
    assert!(
        below as f64 >= 0.99 * checked as f64,
        "riverbed above the water at {} of {checked} segments",
        checked - below
    );
    // the first ring of nodes beyond the water is at its level, the freeboard starts beyond it: one cell out, a
    // bank on a steep stream or in a bend may still lie a little below the level of the segment's midpoint; the
    // few more than half a metre below lie beside a lip or a lower water, where the ground falls away
    assert!(
        banks_ok as f64 >= 0.95 * checked as f64,
        "banks below the water at {} of {checked} segments",
        checked - banks_ok
    );
    assert!(
        banks_strict as f64 >= 0.85 * checked as f64,
        "banks more than {STRICT_BANK:.2} m below the water at {} of {checked} segments",
        checked - banks_strict
    );
}

#[test]
fn terrain_beyond_the_falloff_is_unchanged() {
    let (t, c) = setup();
    let options = WaterfallSceneOptions::default();
    let s = made(&t, &c, &options, 1);
    let d = &s.terrain;
    let mask: Vec<bool> = d
        .constrained
        .iter()
        .zip(&d.overhang_constrained)
        .map(|(a, b)| *a || *b)
        .collect();
    let dist = distance_transform(t.nx, t.ny, t.cell, &mask);
    let (mut far, mut worst, mut changed_near) = (0usize, 0.0f64, 0usize);
    for (k, dist) in dist.iter().enumerate() {
        let change = (d.terrain.heights[k] - t.heights[k]).abs() as f64;
        if *dist as f64 > options.deform.falloff + t.cell {
            far += 1;
            worst = worst.max(change);
        } else if change > 1e-3 {
            changed_near += 1;
        }
    }
    println!(
        "falloff {} m: {far} nodes beyond it, largest change there {worst:.2e} m; {changed_near} nodes changed within it",
        options.deform.falloff
    );
    assert!(far > 0 && changed_near > 0);
    assert!(worst < 1e-3, "a node beyond the falloff moved by {worst} m");
}

#[test]
fn overhangs_push_the_lip_forward_and_the_pool_wall_back() {
    let (t, s) = default_scene();
    let hd = s.horizontal();
    let nx = t.nx;
    let at = |p: DVec2| {
        let f = ((p - t.origin) / t.cell).round();
        let k = f.y as usize * nx + f.x as usize;
        DVec2::new(hd.x.displacement[k], hd.y.displacement[k])
    };
    let mut falls = 0;
    for b in s
        .mesh
        .borders
        .iter()
        .filter(|b| b.part == WaterPart::FreeFall)
    {
        let seg = &s.network.segments[b.element];
        let path = &s.network.paths[seg.arc];
        let u = (path[path.len() - 1] - path[0])
            .truncate()
            .normalize_or_zero();
        let lip = 0.5 * (b.points[0] + b.points[1]).truncate();
        let forward = at(lip).dot(u);
        // the receiving pool's wall straight behind the foot, against the flow
        let to = s.network.graph.arcs[seg.arc].to;
        let Some(pool) = s.mesh.pools.iter().find(|p| p.node == to) else {
            continue;
        };
        let centre = pool.contour.iter().copied().sum::<DVec2>() / pool.contour.len() as f64;
        // the back-facing part of the contour, away from the lip (where both constraints meet, the lip wins)
        let (l0, l1) = (b.points[0].truncate(), b.points[1].truncate());
        let back: Vec<DVec2> = pool
            .contour
            .iter()
            .copied()
            .filter(|p| {
                let m = *p - centre;
                m.dot(u) <= -0.5 * m.length()
                    && worldpaint_core::segment_distance(*p, l0, l1) > 2.0 * t.cell
            })
            .collect();
        if back.is_empty() {
            println!("free-fall {}: lip moves {forward:.3} m along the flow; its lip spans the pool's back wall", seg.arc);
            assert!(
                forward > 0.5,
                "lip of free-fall {} moves {forward} m",
                seg.arc
            );
            continue;
        }
        let backward = back.iter().map(|p| at(*p).dot(u)).sum::<f64>() / back.len() as f64;
        println!(
            "free-fall {}: lip moves {forward:.3} m along the flow, pool back wall {backward:.3} m",
            seg.arc
        );
        assert!(
            forward > 0.5,
            "lip of free-fall {} moves {forward} m",
            seg.arc
        );
        assert!(
            backward < -0.5,
            "back wall under free-fall {} moves {backward} m",
            seg.arc
        );
        falls += 1;
        println!("{falls} exemplar falls checked");
    }
    // the exemplar's lips lie over their pools' back walls; one fall with room between them
    let cliff = |x: f64| {
        if x < 100.0 {
            50.0 - 0.05 * x
        } else {
            30.0 - 0.05 * x
        }
    };
    let (nx, ny) = (201, 101);
    let heights = (0..nx * ny)
        .map(|k| cliff((k % nx) as f64) as f32)
        .collect();
    let t = Heightfield::new(DVec2::ZERO, 1.0, nx, ny, heights).unwrap_or_else(|e| panic!("{e}"));
    let at_x = |x: f64| DVec3::new(x, 50.0, cliff(x));
    let level = cliff(112.0);
    let pool: Vec<DVec3> = (0..16)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / 16.0;
            DVec3::new(112.0 + 6.0 * a.cos(), 50.0 + 6.0 * a.sin(), level)
        })
        .collect();
    let controllers = vec![
        Controller::new(
            ControllerKind::Contact,
            (0..9).map(|k| at_x(20.0 + 10.0 * k as f64)).collect(),
        )
        .with_strength(2.0),
        Controller::new(
            ControllerKind::FreeFall,
            vec![at_x(100.0), DVec3::new(110.0, 50.0, level)],
        ),
        Controller::new(ControllerKind::Pool, pool),
        Controller::new(
            ControllerKind::Contact,
            (0..8)
                .map(|k| DVec3::new(118.0 + 10.0 * k as f64, 50.0, level - 0.5 * k as f64))
                .collect(),
        ),
    ];
    let s = made(&t, &controllers, &WaterfallSceneOptions::default(), 1);
    let hd = s.horizontal();
    let d = |p: DVec2| {
        let f = ((p - t.origin) / t.cell).round();
        let k = f.y as usize * nx + f.x as usize;
        DVec2::new(hd.x.displacement[k], hd.y.displacement[k])
    };
    let (lip, back) = (d(DVec2::new(100.0, 50.0)), d(DVec2::new(106.0, 50.0)));
    println!(
        "a fall off a cliff: lip moves {:.3} m along the flow, the pool's back wall {:.3} m",
        lip.x, back.x
    );
    assert!(lip.x > 0.5 && back.x < -0.5, "lip {lip}, back wall {back}");
}

/// Plan area (m²) of the contact water drawn over by more than one arc, and the whole contact water's, sampled
/// every 25 cm.
fn overlap_of_arcs(s: &WaterfallScene) -> (f64, f64) {
    let step = 0.25;
    let mesh = &s.mesh;
    let mut claimed: std::collections::HashMap<(i64, i64), usize> =
        std::collections::HashMap::new();
    let mut overlap = std::collections::HashSet::new();
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|v| v as usize);
        if mesh.part[a] != WaterPart::Contact {
            continue;
        }
        let arc = s.network.segments[mesh.element[a]].arc;
        let [pa, pb, pc] = [a, b, c].map(|v| mesh.vertices[v].truncate());
        let (lo, hi) = (pa.min(pb).min(pc), pa.max(pb).max(pc));
        let side = |u: DVec2, v: DVec2, p: DVec2| (v - u).perp_dot(p - u);
        for j in (lo.y / step).ceil() as i64..=(hi.y / step).floor() as i64 {
            for i in (lo.x / step).ceil() as i64..=(hi.x / step).floor() as i64 {
                let p = DVec2::new(i as f64, j as f64) * step;
                let d = [side(pa, pb, p), side(pb, pc, p), side(pc, pa, p)];
                if !(d.iter().all(|x| *x >= 0.0) || d.iter().all(|x| *x <= 0.0)) {
                    continue;
                }
                match claimed.get(&(i, j)) {
                    Some(&other) if other != arc => {
                        overlap.insert((i, j));
                    }
                    Some(_) => {}
                    None => {
                        claimed.insert((i, j), arc);
                    }
                }
            }
        }
    }
    let cell = step * step;
    (overlap.len() as f64 * cell, claimed.len() as f64 * cell)
}

#[test]
fn smaller_ribbons_end_inside_the_larger_at_junctions() {
    let (_, s) = default_scene();
    let (overlap, total) = overlap_of_arcs(&s);
    println!(
        "contact water drawn twice: {overlap:.0} m² of {total:.0} m² ({:.2} %) at {} branches",
        100.0 * overlap / total,
        s.report.branches
    );
    assert!(total > 1000.0, "only {total} m² of contact water");
    // drawing every ribbon whole draws 10.6 % of it twice; the rest is the one row kept inside the larger ribbon
    assert!(
        overlap <= 0.03 * total,
        "{overlap} m² of the water drawn twice"
    );
}

#[test]
fn maps_foam_and_footprint() {
    let (t, s) = default_scene();
    let m = &s.maps;
    // mean foam per type over the water nodes of that type's segments (by the node's nearest mesh vertex would
    // need a search; the footprint is rebuilt instead)
    let fp = match worldpaint_core::waterfall_footprint(
        &t,
        &s.network,
        &s.mesh,
        &WaterfallSceneOptions::default().integration,
        0.0,
    ) {
        Ok(f) => f,
        Err(e) => panic!("{e}"),
    };
    let mut by_type: std::collections::BTreeMap<String, (f64, usize)> = Default::default();
    for (k, n) in fp.nodes.iter().enumerate() {
        let Some(n) = n else { continue };
        if n.inside <= 0.0 || n.part != WaterPart::Contact {
            continue;
        }
        let ty = s.network.segments[n.element].kind_of_water;
        let e = by_type.entry(format!("{ty:?}")).or_default();
        e.0 += m.foam[k] as f64;
        e.1 += 1;
    }
    for (ty, (sum, n)) in &by_type {
        println!("{ty}: {n} water nodes, mean foam {:.3}", sum / *n as f64);
    }
    let mean = |ty: WaterfallType| by_type.get(&format!("{ty:?}")).map(|(s, n)| s / *n as f64);
    let river = mean(WaterfallType::River).or(mean(WaterfallType::Stream));
    let foamy = [
        WaterfallType::Cascade,
        WaterfallType::Horsetail,
        WaterfallType::Block,
    ]
    .iter()
    .filter_map(|t| mean(*t))
    .fold(f64::NAN, f64::max);
    println!("foam: gentle river {river:?}, steepest foamy contact type {foamy:.3}");
    if let Some(r) = river {
        assert!(foamy > r + 0.2, "foam on cascades {foamy} vs river {r}");
    }
    // the plunge pools: foam near the foot of every free-fall
    for (a, arc) in s.network.graph.arcs.iter().enumerate() {
        if arc.kind != ControllerKind::FreeFall {
            continue;
        }
        let foot = s.network.paths[a][s.network.paths[a].len() - 1].truncate();
        let k = m.node(foot).unwrap_or(0);
        println!(
            "free-fall {a} ({:?}): foam at its foot {:.2}",
            s.network.segments[s.network.segment_ranges[a].start].kind_of_water, m.foam[k]
        );
    }
    // the footprint covers the mesh: every contact and pool triangle's centroid is water
    let mut total = 0;
    let mut covered = 0;
    for tri in &s.mesh.triangles {
        let v = tri.map(|i| i as usize);
        if v.iter().any(|i| s.mesh.part[*i] == WaterPart::FreeFall) {
            continue;
        }
        let centroid =
            (s.mesh.vertices[v[0]] + s.mesh.vertices[v[1]] + s.mesh.vertices[v[2]]) / 3.0;
        total += 1;
        if m.is_water(centroid.truncate()) {
            covered += 1;
        }
    }
    let water_area = m.water.iter().filter(|w| **w > 0.5).count() as f64 * t.cell * t.cell;
    println!(
        "footprint: {covered} of {total} mesh triangles' centroids in the water map; water {water_area:.0} m², mesh {:.0} m²",
        s.mesh.area()
    );
    assert!(
        covered as f64 >= 0.97 * total as f64,
        "{covered} of {total} covered"
    );
    // the speed map: zero outside the water, and along the flow on the axes
    let dry_moving = (0..m.water.len())
        .filter(|k| m.water[*k] < 0.5 && m.speed[*k] != DVec2::ZERO)
        .count();
    assert_eq!(dry_moving, 0);
}

/// Whether the rock stands in the water, on a wet node of the rock map's support, on the riverbed.
fn on_the_riverbed(s: &WaterfallScene, r: &Rock) -> bool {
    let m = &s.maps;
    let p = r.position.truncate();
    let node = m.node(p).filter(|k| m.rocks[*k] > 0.0 && m.water[*k] > 0.5);
    let ground = height(&s.terrain.terrain, p);
    m.is_water(p) && node.is_some() && (r.position.z - ground).abs() < 1e-6
}

/// `∫ f(p, rock map) dA` over the water, on a lattice of an eighth of a cell (the map read bilinearly, as the
/// synthesis reads it).
fn over_the_water(s: &WaterfallScene, f: impl Fn(DVec2, f64) -> f64) -> f64 {
    let m = &s.maps;
    let mut t = s.terrain.terrain.clone();
    if let Err(e) = t.add_map("rocks", m.rocks.clone()) {
        panic!("{e}");
    }
    let step = m.cell / 8.0;
    let (lo, hi) = t.bbox();
    let (nx, ny) = (
        ((hi - lo) / step).floor().x as usize,
        ((hi - lo) / step).floor().y as usize,
    );
    let mut sum = 0.0;
    for j in 0..ny {
        for i in 0..nx {
            let p = lo + (DVec2::new(i as f64, j as f64) + 0.5) * step;
            if m.is_water(p) {
                sum += f(p, t.map_at("rocks", p).unwrap_or(0.0)) * step * step;
            }
        }
    }
    sum
}

/// The smallest distance between two rocks.
fn closest_pair(rocks: &[Rock]) -> f64 {
    let mut best = f64::INFINITY;
    for (i, a) in rocks.iter().enumerate() {
        for b in &rocks[i + 1..] {
            best = best.min(a.position.truncate().distance(b.position.truncate()));
        }
    }
    best
}

/// The built-in river-rock color (an asset of the product) is the river-rock exemplar learned on its rock map. With
/// `WORLDPAINT_WRITE_ASSETS=1` this test writes the asset anew (after a change to the analysis, say).
#[test]
fn the_built_in_rock_color_is_the_river_rock_exemplar_learned() {
    let scene = river_rocks(1);
    let Some((min, max)) = scene.terrain.as_deref().map(|t| t.bbox()) else {
        panic!("the river-rock exemplar has a terrain");
    };
    let options = AnalysisOptions {
        maps: vec![ROCK_MAP.into()],
        ..Default::default()
    };
    let learned = match learn_color(&scene, &Region::Rect { min, max }, "River rocks", &options) {
        Ok(c) => c,
        Err(e) => panic!("{e}"),
    };
    if std::env::var_os("WORLDPAINT_WRITE_ASSETS").is_some() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../assets/waterfall/river_rocks.color.json");
        let json = learned.to_json().map_err(|e| e.to_string());
        if let Err(e) =
            json.and_then(|j| std::fs::write(&path, j + "\n").map_err(|e| e.to_string()))
        {
            panic!("writing {}: {e}", path.display());
        }
    }
    match river_rock_color() {
        Ok(builtin) => assert!(
            *builtin == learned,
            "the river-rock asset differs from the exemplar learned"
        ),
        Err(e) => panic!("{e}"),
    }
}

#[test]
fn the_built_in_rock_color_prefers_rocky_water_and_keeps_its_spacing() {
    let c = match river_rock_color() {
        Ok(c) => c,
        Err(e) => panic!("{e}"),
    };
    let cat = &c.categories[0];
    println!(
        "river rocks: {} in the exemplar, {:.4} per m², closest pair {:.2} m, rdf bins of {:.2} m to {:.1} m",
        cat.count, cat.density, cat.min_distance, c.bin_width, c.max_radius
    );
    assert_eq!(cat.category.name, RIVER_ROCK_CATEGORY);
    // the hard core: no pair closer than the spacing, and the rdf empty below it
    assert!(cat.min_distance >= RIVER_ROCK_SPACING);
    let Some(Interaction::Rdf { hist }) = c.pairs.first().map(|p| &p.interaction) else {
        panic!("no rdf");
    };
    let core_bins = (RIVER_ROCK_SPACING / hist.bin_width).floor() as usize;
    assert!(hist.values[..core_bins].iter().all(|v| *v == 0.0));
    // the preference ψ = h / q per bin of the rock map: 0 on the map's zeros, growing with it
    let Some(m) = c.maps.iter().find(|m| m.map == ROCK_MAP) else {
        panic!("the color follows no rock map");
    };
    let psi: Vec<f64> = m
        .hist
        .values
        .iter()
        .zip(&m.region_hist.values)
        .map(|(h, q)| if *q > 0.0 { h / q } else { 0.0 })
        .collect();
    let mid = |k: usize| m.hist.start + (k as f64 + 0.5) * m.hist.bin_width;
    println!(
        "ψ(rock map): {}",
        psi.iter()
            .enumerate()
            .map(|(k, v)| format!("{:.2}: {v:.2}", mid(k)))
            .collect::<Vec<_>>()
            .join(", ")
    );
    assert_eq!(psi[0], 0.0, "rocks where the map is 0");
    let n = psi.len();
    let quarter = |range: std::ops::Range<usize>| psi[range].iter().sum::<f64>() / (n / 4) as f64;
    let (low, high) = (quarter(1..1 + n / 4), quarter(n - n / 4..n));
    println!("mean ψ over the lowest quarter of the map {low:.2}, over the highest {high:.2}");
    assert!(high > 3.0 * low, "rocks prefer high rock-map values");
    // λ ψ(m) is the exemplar's intensity 0.08 m, within its noise
    for (k, v) in psi.iter().enumerate().skip(2) {
        let intensity = cat.density * v;
        let wanted = RIVER_ROCK_DENSITY * mid(k);
        assert!(
            (intensity - wanted).abs() <= 0.3 * wanted + 0.004,
            "bin {k}: λψ = {intensity:.4} for 0.08 m = {wanted:.4}"
        );
    }
}

#[test]
fn rocks_stand_in_the_water_as_dense_as_the_rock_map_says() {
    let (_, s) = default_scene();
    let m = &s.maps;
    assert!(!s.rocks.is_empty(), "no rock");
    let off = s.rocks.iter().filter(|r| !on_the_riverbed(&s, r)).count();
    assert_eq!(off, 0, "rocks out of the water or off the riverbed");
    // the count: ∫ 0.08 · rock map dA over the water
    let expected = over_the_water(&s, |_, v| RIVER_ROCK_DENSITY * v);
    let node_sum: f64 = m
        .rocks
        .iter()
        .zip(&m.water)
        .filter(|(_, w)| **w > 0.5)
        .map(|(r, _)| RIVER_ROCK_DENSITY * *r as f64 * m.cell * m.cell)
        .sum();
    let got = s.rocks.len() as f64;
    println!(
        "{got} rocks; ∫ 0.08 · rock map dA over the water {expected:.1} (over the wet nodes' cells {node_sum:.1}): \
         {:+.1} %",
        100.0 * (got / expected - 1.0)
    );
    assert!((got - expected).abs() <= 0.2 * expected);
    // denser where the rock map is higher: the rocks by the rock value of their node, against ∫ 0.08 · rock map dA
    // over the water nearest to such nodes
    let class = |p: DVec2, lo: f32, hi: f32| {
        m.node(p)
            .is_some_and(|k| m.water[k] > 0.5 && m.rocks[k] > lo && m.rocks[k] <= hi)
    };
    let mut by_class = Vec::new();
    for (lo, hi) in [(0.0, 0.3), (0.3, 0.6), (0.6, 1.0)] {
        let want = over_the_water(&s, |p, v| {
            if class(p, lo, hi) {
                RIVER_ROCK_DENSITY * v
            } else {
                0.0
            }
        });
        let area = over_the_water(&s, |p, _| if class(p, lo, hi) { 1.0 } else { 0.0 });
        let got = s
            .rocks
            .iter()
            .filter(|r| class(r.position.truncate(), lo, hi))
            .count() as f64;
        println!(
            "rock map in ({lo}, {hi}]: {got} rocks on {area:.0} m² of water ({:.4} per m²), 0.08 · rock map gives \
             {want:.1} ({:.4} per m²)",
            got / area,
            want / area
        );
        by_class.push((got / area, want / area));
    }
    let (low, high) = (by_class[0], by_class[2]);
    assert!(
        high.0 > 2.0 * low.0,
        "rocks are denser where the rock map is high"
    );
    // the hard core thins the densest places: the model's factor is a preference where the exemplar measured a
    // density
    assert!(high.0 > 0.6 * high.1 && low.0 < 1.2 * low.1);
    // the hard core
    let color = match river_rock_color() {
        Ok(c) => c,
        Err(e) => panic!("{e}"),
    };
    let closest = closest_pair(&s.rocks);
    println!(
        "closest two rocks {closest:.2} m; learned hard core {:.2} m",
        color.categories[0].min_distance
    );
    assert!(closest >= color.categories[0].min_distance - color.bin_width);
    // what the synthesis gives: rotations over the turn, scales of the exemplar
    let turned = s.rocks.iter().filter(|r| r.rotation > 1e-9).count();
    let (smin, smax) = s.rocks.iter().fold((f64::INFINITY, 0.0f64), |(a, b), r| {
        (a.min(r.scale), b.max(r.scale))
    });
    println!("{turned} rocks turned, scales {smin:.2}..{smax:.2}");
    assert!(turned > 0 && smin >= 0.5 && smax <= 1.5 && smax > smin);
    assert_eq!(s.report.rocks, s.rocks.len());
}

#[test]
fn a_learned_color_scatters_rocks_with_its_own_spacing() {
    let (t, c) = setup();
    let square = Region::Rect {
        min: DVec2::ZERO,
        max: DVec2::splat(100.0),
    };
    let (density, spacing) = (0.05, 3.0);
    let points = hard_core_points(&square, density, spacing, 4);
    let exemplar = scene_from_points("Boulder", &points);
    let learned = match learn_color(&exemplar, &square, "Boulders", &AnalysisOptions::default()) {
        Ok(c) => c,
        Err(e) => panic!("{e}"),
    };
    assert!(learned.maps.is_empty(), "learned without any rock map");
    let mut options = WaterfallSceneOptions::default();
    options.decoration.rock_color = Some(learned.clone());
    let s = made(&t, &c, &options, 1);
    let off = s.rocks.iter().filter(|r| !on_the_riverbed(&s, r)).count();
    assert_eq!(off, 0, "boulders out of the water or off the riverbed");
    let closest = closest_pair(&s.rocks);
    // the count: the user's density times ∫ ψ(rock map) dA, ψ the built-in color's preference
    let builtin = match river_rock_color() {
        Ok(c) => c,
        Err(e) => panic!("{e}"),
    };
    let Some(m) = builtin.maps.iter().find(|m| m.map == ROCK_MAP) else {
        panic!("the built-in color follows no rock map");
    };
    let psi = |v: f64| {
        let k = (((v - m.hist.start) / m.hist.bin_width).floor().max(0.0) as usize)
            .min(m.hist.values.len() - 1);
        let q = m.region_hist.values[k];
        if q > 0.0 {
            m.hist.values[k] / q
        } else {
            0.0
        }
    };
    let lambda = learned.categories[0].density;
    let expected = lambda * over_the_water(&s, |_, v| psi(v));
    let got = s.rocks.len() as f64;
    println!(
        "a hard core of {spacing} m at {lambda:.4} per m², learned without a rock map: {got} boulders for \
         λ ∫ ψ dA = {expected:.1} ({:+.1} %); closest two {closest:.2} m (learned {:.2} m)",
        100.0 * (got / expected - 1.0),
        learned.categories[0].min_distance
    );
    assert!(closest >= learned.categories[0].min_distance - learned.bin_width);
    assert!(closest >= spacing - learned.bin_width);
    assert!((got - expected).abs() <= 0.2 * expected);
    assert!(s.rocks.iter().all(|r| r.category == 0));
}

#[test]
fn same_seed_same_scene() {
    let (t, c) = setup();
    let a = made(&t, &c, &WaterfallSceneOptions::default(), 5);
    let b = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .map(|p| p.install(|| made(&t, &c, &WaterfallSceneOptions::default(), 5)))
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(a.report, b.report);
    assert_eq!(a.terrain.terrain.heights, b.terrain.terrain.heights);
    assert_eq!(a.mesh.vertices, b.mesh.vertices);
    assert_eq!(a.maps.foam, b.maps.foam);
    assert_eq!(a.rocks, b.rocks);
    let other = made(&t, &c, &WaterfallSceneOptions::default(), 6);
    assert_ne!(a.rocks, other.rocks);
    println!("seed 5 twice (all threads, one thread): identical; seed 6 differs");
}

#[test]
fn bad_options_are_refused() {
    let (t, c) = setup();
    let mut o = WaterfallSceneOptions::default();
    o.deform.falloff = f64::NAN;
    assert!(build_waterfall_scene(&t, &c, &WaterfallParams::default(), &o, 1).is_err());
    let mut o = WaterfallSceneOptions::default();
    o.integration.min_width = 0.0;
    assert!(build_waterfall_scene(&t, &c, &WaterfallParams::default(), &o, 1).is_err());
    // a rock color with nothing to scatter
    let square = Region::Rect {
        min: DVec2::ZERO,
        max: DVec2::splat(50.0),
    };
    let points = hard_core_points(&square, 0.05, 2.0, 1);
    let mut color = match learn_color(
        &scene_from_points("Boulder", &points),
        &square,
        "Boulders",
        &AnalysisOptions::default(),
    ) {
        Ok(c) => c,
        Err(e) => panic!("{e}"),
    };
    color.categories.clear();
    color.pairs.clear();
    let mut o = WaterfallSceneOptions::default();
    o.decoration.rock_color = Some(color);
    let e = build_waterfall_scene(&t, &c, &WaterfallParams::default(), &o, 1)
        .err()
        .map(|e| e.to_string());
    println!("refused: {e:?}");
    assert!(e.is_some_and(|m| m.contains("no distribution category")));
}
