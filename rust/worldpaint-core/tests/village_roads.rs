//! The village road search (thesis 3.2.4): straightness, the move mask, grades and serpentines, re-use, water,
//! buildings and walls, cycles, unreachable buildings, bad inputs and determinism.

use glam::DVec2;
use worldpaint_core::{Error, Grid, Land, Road, RoadConnection, RoadNetwork, RoadParams};

const CELL: f64 = 2.0;

fn params() -> RoadParams {
    RoadParams {
        width: 4.0,
        distance_weight: 1.0,
        slope_weight: 2.0,
        max_grade: 0.12,
        curvature_weight: 2.0,
        water_weight: 20.0,
        building_cost: 500.0,
        reuse_weight: 0.1,
        mask_radius: 3,
        cycle_angle_degrees: 30.0,
        cycle_max_length: 150.0,
        cycle_min_separation: 25.0,
        street_length: 0.0,
    }
}

/// A `size × size` m land at 2 m cells, heights from `h`, all inside, dry, no walls.
fn land(size: f64, h: impl Fn(DVec2) -> f64) -> Land {
    let n = (size / CELL).round() as usize + 1;
    let grid = Grid {
        origin: DVec2::ZERO,
        cell: CELL,
        nx: n,
        ny: n,
    };
    Land::from_maps(
        grid,
        (0..grid.len())
            .map(|k| h(grid.point_of(k)) as f32)
            .collect(),
        [
            vec![true; grid.len()],
            vec![false; grid.len()],
            vec![false; grid.len()],
            vec![false; grid.len()],
        ],
    )
    .expect("land")
}

fn set(land: &mut Land, what: impl Fn(&mut Land, usize), area: impl Fn(DVec2) -> bool) {
    for k in 0..land.grid().len() {
        if area(land.grid().point_of(k)) {
            what(land, k);
        }
    }
}

fn length(road: &Road) -> f64 {
    road.points.windows(2).map(|w| w[0].distance(w[1])).sum()
}

/// Points every `step` metres along a road.
fn along(road: &Road, step: f64) -> Vec<DVec2> {
    let mut out = Vec::new();
    for w in road.points.windows(2) {
        let n = (w[0].distance(w[1]) / step).ceil().max(1.0) as usize;
        for s in 0..=n {
            out.push(w[0] + (w[1] - w[0]) * (s as f64 / n as f64));
        }
    }
    out
}

/// Steepest grade along a road, sampled every 0.25 m on the terrain.
fn steepest(land: &Land, road: &Road) -> f64 {
    let mut g: f64 = 0.0;
    for w in road.points.windows(2) {
        let n = (w[0].distance(w[1]) / 0.25).ceil().max(1.0) as usize;
        let step = w[0].distance(w[1]) / n as f64;
        for s in 0..n {
            let a = w[0] + (w[1] - w[0]) * (s as f64 / n as f64);
            let b = w[0] + (w[1] - w[0]) * ((s + 1) as f64 / n as f64);
            g = g.max((land.height_at(b) - land.height_at(a)).abs() / step);
        }
    }
    g
}

/// Steepest grade along a road sampled as the search does: each segment is a run of one grid move `(dx, dy)`,
/// sampled `ceil(2 |(dx, dy)|)` times per move (at most half a cell apart).
fn steepest_per_move(land: &Land, road: &Road) -> f64 {
    fn gcd(a: i64, b: i64) -> i64 {
        if b == 0 {
            a
        } else {
            gcd(b, a % b)
        }
    }
    let mut g: f64 = 0.0;
    for w in road.points.windows(2) {
        let d = (w[1] - w[0]) / land.grid().cell;
        let (dx, dy) = (d.x.round() as i64, d.y.round() as i64);
        let runs = gcd(dx.abs(), dy.abs()).max(1);
        let step = DVec2::new((dx / runs) as f64, (dy / runs) as f64);
        let n = (2.0 * step.length()).ceil() as i64 * runs;
        let sub = w[0].distance(w[1]) / n as f64;
        for s in 0..n {
            let a = w[0] + (w[1] - w[0]) * (s as f64 / n as f64);
            let b = w[0] + (w[1] - w[0]) * ((s + 1) as f64 / n as f64);
            g = g.max((land.height_at(b) - land.height_at(a)).abs() / sub);
        }
    }
    g
}

/// Metres of a road over nodes where `flag` holds (nearest node, sampled every 0.25 m).
fn metres_over(land: &Land, road: &Road, flag: impl Fn(usize) -> bool) -> f64 {
    let pts = along(road, 0.25);
    pts.windows(2)
        .filter(|w| flag(land.grid().nearest_clamped(0.5 * (w[0] + w[1]))))
        .map(|w| w[0].distance(w[1]))
        .sum()
}

fn connect(
    net: &mut RoadNetwork,
    land: &Land,
    p: &RoadParams,
    occupied: &[bool],
    from: DVec2,
) -> RoadConnection {
    net.connect(land, p, occupied, from, 0.0)
        .expect("valid input")
}

/// A network of the one connection point `psi` on `land`, and the connection of a first building at `b` to it
/// over unbuilt land.
fn first_road(land: &Land, psi: DVec2, p: &RoadParams, b: DVec2) -> (RoadNetwork, RoadConnection) {
    let mut net = RoadNetwork::new(land, &[psi], &[]).unwrap();
    let c = connect(&mut net, land, p, &vec![false; land.grid().len()], b);
    (net, c)
}

/// Named so that the village tests can be run together (`cargo test village`).
mod village {
    use super::*;

    #[test]
    fn a_house_near_a_linked_road_fronts_it_instead_of_getting_a_dead_end() {
        let land = land(300.0, |_| 10.0);
        let free = vec![false; land.grid().len()];
        let psi = DVec2::new(0.0, 150.0);
        let (mut net, street) = first_road(&land, psi, &params(), DVec2::new(280.0, 150.0));
        assert!(street.reached && street.roads.len() == 1);
        let roads = net.roads.len();
        // 10 m beside the street: within a frontage of 13.5 m, served without a road of its own
        let near = DVec2::new(140.0, 160.0);
        let c = net.connect(&land, &params(), &free, near, 13.5).unwrap();
        assert!(c.reached && c.roads.is_empty(), "{c:?}");
        assert_eq!(net.roads.len(), roads);
        // 30 m beside it: a road of its own
        let far = DVec2::new(140.0, 180.0);
        let c = net.connect(&land, &params(), &free, far, 13.5).unwrap();
        assert!(c.reached && !c.roads.is_empty(), "{c:?}");
        // without a frontage, the near house gets its road too
        let c = connect(&mut net, &land, &params(), &free, DVec2::new(100.0, 160.0));
        assert!(c.reached && !c.roads.is_empty(), "{c:?}");
    }

    #[test]
    fn a_road_on_flat_land_is_nearly_straight_and_the_move_mask_matters() {
        let land = land(400.0, |_| 10.0);
        let psi = DVec2::new(0.0, 100.0);
        let b = DVec2::new(300.0, 250.0); // offset (300, 150): direction (2, 1)
        let straight = psi.distance(b);
        let mut lengths = Vec::new();
        for radius in [1, 2, 3] {
            let p = RoadParams {
                mask_radius: radius,
                ..params()
            };
            let (net, c) = first_road(&land, psi, &p, b);
            assert!(c.reached && c.roads.len() == 1 && !c.over_max_grade);
            let road = &net.roads[c.roads[0]];
            assert_eq!(road.points[0], b);
            assert_eq!(*road.points.last().unwrap(), psi);
            lengths.push(length(road));
        }
        println!("straight {straight:.1} m, mask 1/2/3: {lengths:.1?}");
        // 8 moves: a diagonal and a straight run, sqrt(2)+1 over sqrt(5) = 8 % longer
        assert!(lengths[0] > 1.06 * straight, "{lengths:?}");
        // (2, 1) is a move of the 16- and 32-move masks
        assert!(lengths[1] < 1.01 * straight, "{lengths:?}");
        assert!(lengths[2] < 1.01 * straight, "{lengths:?}");
        // a direction off every mask: (5, 1)
        let b = DVec2::new(250.0, 150.0);
        let (net, c) = first_road(&land, psi, &params(), b);
        let l = length(&net.roads[c.roads[0]]);
        assert!(l < 1.02 * psi.distance(b), "{l} vs {}", psi.distance(b));
        // a few turning vertices only (collinear moves merged)
        assert!(net.roads[c.roads[0]].points.len() <= 4);
        // distances to the network
        let r = &net.roads[c.roads[0]].points;
        assert!(net.distance(0.5 * (r[0] + r[1])) < 1e-9);
        let off = 0.5 * (r[0] + r[1]) + 7.0 * (r[1] - r[0]).perp().normalize();
        assert!((net.distance(off) - 7.0).abs() < 1e-6);
    }

    #[test]
    fn roads_keep_to_the_grade_limit_with_serpentines() {
        // a ramp of grade 0.35 along x, in a band 120 m wide: climbing 35 m to x = 100 takes three legs at least
        let mut land = land(300.0, |p| 0.35 * p.x);
        set(
            &mut land,
            |l, k| l.inside_mut()[k] = false,
            |q| (q.y - 150.0).abs() > 60.0,
        );
        let p = params();
        let psi = DVec2::new(0.0, 150.0);
        let b = DVec2::new(100.0, 150.0);
        let (net, c) = first_road(&land, psi, &p, b);
        assert!(c.reached && !c.over_max_grade);
        let road = &net.roads[c.roads[0]];
        let g = steepest(&land, road);
        let hairpins = road
            .points
            .windows(3)
            .filter(|w| (w[1].y - w[0].y) * (w[2].y - w[1].y) < 0.0)
            .count();
        println!(
            "ramp 0.35: road {:.0} m, {hairpins} hairpins, steepest {g:.4} (reported {:.4})",
            length(road),
            c.steepest_grade
        );
        assert!(c.steepest_grade <= p.max_grade + 1e-6);
        assert!(g <= p.max_grade + 1e-6, "{g}");
        assert!(length(road) >= 35.0 / p.max_grade - 1.0);
        assert!(hairpins >= 2, "{:?}", road.points);

        // grade 0.4: no move of the 32-move mask is gentle enough across it (the gentlest, (1, 3), climbs 0.126),
        // so the road is built over the limit; the 48 moves of radius 4 have (1, 4), at 0.097
        let land = land_ramp(0.4);
        let (_, c) = first_road(&land, psi, &p, b);
        assert!(c.reached && c.over_max_grade && c.steepest_grade > p.max_grade);
        let p4 = RoadParams {
            mask_radius: 4,
            ..params()
        };
        let (net, c) = first_road(&land, psi, &p4, b);
        assert!(c.reached && !c.over_max_grade);
        assert!(steepest(&land, &net.roads[c.roads[0]]) <= p.max_grade + 1e-6);

        // a cone of grade 0.3: climb from its foot to near its top
        let land = land_cone();
        let (net, c) = first_road(&land, DVec2::new(0.0, 0.0), &p, DVec2::new(200.0, 240.0));
        assert!(c.reached && !c.over_max_grade);
        let road = &net.roads[c.roads[0]];
        let (g, fine) = (steepest_per_move(&land, road), steepest(&land, road));
        println!(
            "cone 0.3: road {:.0} m, steepest {g:.4} sampled per move, {fine:.4} every 0.25 m",
            length(road)
        );
        assert!(g <= p.max_grade + 1e-6, "{g}");
        // within a cell the bilinear surface of the cone bends: finer samples find a little more
        assert!(fine <= 1.06 * p.max_grade, "{fine}");
    }

    fn land_ramp(grade: f64) -> Land {
        land(300.0, |p| grade * p.x)
    }

    fn land_cone() -> Land {
        land(400.0, |p| {
            (60.0 - 0.3 * p.distance(DVec2::new(200.0, 200.0))).max(0.0)
        })
    }

    #[test]
    fn a_cliff_across_the_land_is_climbed_over_the_limit_and_said_so() {
        // flat below y = 100, a 30 m cliff band 6 m wide, flat above
        let land = land(300.0, |p| 30.0 * ((p.y - 100.0) / 6.0).clamp(0.0, 1.0));
        let free = vec![false; land.grid().len()];
        let p = params();
        let (mut net, c) = first_road(&land, DVec2::new(150.0, 0.0), &p, DVec2::new(150.0, 200.0));
        assert!(c.reached && c.over_max_grade);
        assert!(c.steepest_grade > 1.0, "{}", c.steepest_grade);
        let road = &net.roads[c.roads[0]];
        // the steep part is as short as the cliff allows: the road is still about straight
        assert!(length(road) < 1.1 * 200.0, "{}", length(road));
        // a second building on the plateau joins that road within the limit
        let c2 = connect(&mut net, &land, &p, &free, DVec2::new(230.0, 230.0));
        assert!(c2.reached && !c2.over_max_grade);
        assert!(length(&net.roads[c2.roads[0]]) < 90.0);
    }

    #[test]
    fn a_new_road_ends_on_the_centre_line_of_the_road_it_joins() {
        // a first road at a slant: the nodes it passes over lie up to a cell off its centre line
        let land = land(400.0, |_| 0.0);
        let free = vec![false; land.grid().len()];
        let mut net = RoadNetwork::new(&land, &[DVec2::new(0.0, 20.0)], &[]).unwrap();
        let p = RoadParams {
            cycle_max_length: 0.0,
            ..params()
        };
        let homes = [
            DVec2::new(390.0, 250.0),
            DVec2::new(150.0, 160.0),
            DVec2::new(260.0, 110.0),
            DVec2::new(330.0, 290.0),
            DVec2::new(90.0, 110.0),
            DVec2::new(220.0, 230.0),
        ];
        for h in homes {
            assert!(connect(&mut net, &land, &p, &free, h).reached);
        }
        let on_road = |q: DVec2, roads: &[Road]| {
            roads
                .iter()
                .flat_map(|r| r.points.windows(2))
                .map(|w| worldpaint_core::segment_distance(q, w[0], w[1]))
                .fold(f64::INFINITY, f64::min)
        };
        for k in 1..net.roads.len() {
            let end = *net.roads[k].points.last().unwrap();
            let gap = on_road(end, &net.roads[..k]);
            assert!(
                gap < 1e-6,
                "road {k} ends {gap:.3} m from the roads before it"
            );
        }
    }

    #[test]
    fn a_street_goes_on_past_its_house_until_the_land_stops_it() {
        let mut land = land(300.0, |_| 10.0);
        // a pond from x = 230 m on
        set(&mut land, |l, k| l.water_mut()[k] = true, |p| p.x >= 230.0);
        let free = vec![false; land.grid().len()];
        let psi = DVec2::new(0.0, 150.0);
        let street = |length: f64, house: DVec2| {
            let p = RoadParams {
                street_length: length,
                cycle_max_length: 0.0,
                ..params()
            };
            let mut net = RoadNetwork::new(&land, &[psi], &[]).unwrap();
            let c = connect(&mut net, &land, &p, &free, house);
            let laid = net.lay_street(&land, &p, &free, c.roads[0]);
            (laid, net.roads[c.roads[0]].points[0])
        };
        // 40 m asked on open land: 40 m laid, straight on from the house, away from Ψ
        let (laid, end) = street(40.0, DVec2::new(150.0, 150.0));
        assert_eq!(laid, 40.0);
        assert!((end - DVec2::new(190.0, 150.0)).length() < 1e-9, "{end:?}");
        // towards the pond: it stops on the dry land before it
        let (laid, end) = street(100.0, DVec2::new(150.0, 150.0));
        assert!(laid < 80.0 && end.x < 230.0, "{laid} m to {end:?}");
        assert!(end.x >= 226.0, "{laid} m to {end:?}");
        // none asked, none laid
        assert_eq!(street(0.0, DVec2::new(150.0, 150.0)).0, 0.0);
    }

    #[test]
    fn new_buildings_re_use_the_roads() {
        let land = land(400.0, |_| 0.0);
        let free = vec![false; land.grid().len()];
        let psi = DVec2::new(0.0, 200.0);
        let mut net = RoadNetwork::new(&land, &[psi], &[]).unwrap();
        let p = params();
        connect(&mut net, &land, &p, &free, DVec2::new(350.0, 200.0));
        let b = DVec2::new(250.0, 260.0);
        let c = connect(&mut net, &land, &p, &free, b);
        let road = &net.roads[c.roads[0]];
        println!(
            "second road {:.1} m, straight to Ψ {:.1} m",
            length(road),
            b.distance(psi)
        );
        assert!(length(road) < 0.3 * b.distance(psi));
        assert!((road.points.last().unwrap().y - 200.0).abs() < 1e-9);

        // total road length for a fan of buildings, with and without re-use
        let homes = [
            DVec2::new(350.0, 200.0),
            DVec2::new(300.0, 300.0),
            DVec2::new(320.0, 90.0),
            DVec2::new(220.0, 340.0),
            DVec2::new(200.0, 60.0),
            DVec2::new(380.0, 330.0),
        ];
        let total = |reuse: f64| {
            let p = RoadParams {
                reuse_weight: reuse,
                cycle_max_length: 0.0,
                ..params()
            };
            let mut net = RoadNetwork::new(&land, &[psi], &[]).unwrap();
            for &h in &homes {
                assert!(connect(&mut net, &land, &p, &free, h).reached);
            }
            net.roads.iter().map(length).sum::<f64>()
        };
        let (with, without) = (total(0.1), total(1.0));
        println!("total road length: re-use 0.1 {with:.0} m, 1.0 {without:.0} m");
        assert!(with < 0.8 * without);
    }

    #[test]
    fn roads_avoid_water_unless_there_is_no_dry_way() {
        let p = RoadParams {
            cycle_max_length: 0.0,
            ..params()
        };
        let psi = DVec2::new(0.0, 200.0);
        let b = DVec2::new(300.0, 200.0);
        // a river 20 m wide across the land, with a dry gap at the top
        let mut dry_gap = land(400.0, |_| 0.0);
        set(
            &mut dry_gap,
            |l, k| l.water_mut()[k] = true,
            |q| (140.0..=160.0).contains(&q.x) && q.y < 300.0,
        );
        let (net, c) = first_road(&dry_gap, psi, &p, b);
        let wet = metres_over(&dry_gap, &net.roads[c.roads[0]], |k| dry_gap.water()[k]);
        println!("with a dry way: {wet:.1} m in water");
        assert_eq!(wet, 0.0);
        // the same river all across: one crossing, about its width
        let mut river = land(400.0, |_| 0.0);
        set(
            &mut river,
            |l, k| l.water_mut()[k] = true,
            |q| (140.0..=160.0).contains(&q.x),
        );
        let (net, c) = first_road(&river, psi, &p, b);
        assert!(c.reached);
        let wet = metres_over(&river, &net.roads[c.roads[0]], |k| river.water()[k]);
        println!("no dry way: {wet:.1} m in water");
        assert!(wet > 15.0 && wet < 26.0, "{wet}");
    }

    #[test]
    fn roads_go_round_buildings_and_through_the_gate() {
        let p = RoadParams {
            cycle_max_length: 0.0,
            ..params()
        };
        let mut l = land(400.0, |_| 0.0);
        let psi = DVec2::new(0.0, 200.0);
        let b = DVec2::new(350.0, 200.0);
        // a house block in the way
        let occupied: Vec<bool> = (0..l.grid().len())
            .map(|k| {
                let q = l.grid().point_of(k);
                (150.0..=190.0).contains(&q.x) && (170.0..=230.0).contains(&q.y)
            })
            .collect();
        // a wall across the land at x = 260 with a gate at y 290..300
        set(
            &mut l,
            |l, k| l.wall_mut()[k] = true,
            |q| (q.x - 260.0).abs() < 1.0 && !(290.0..=300.0).contains(&q.y),
        );
        let mut net = RoadNetwork::new(&l, &[psi], &[]).unwrap();
        let c = connect(&mut net, &l, &p, &occupied, b);
        let road = &net.roads[c.roads[0]];
        let over_houses = metres_over(&l, road, |k| occupied[k]);
        let over_wall = metres_over(&l, road, |k| l.wall()[k]);
        println!(
            "road {:.0} m, {over_houses} m over houses, {over_wall} m over the wall",
            length(road)
        );
        assert_eq!(over_houses, 0.0);
        assert_eq!(over_wall, 0.0);
        // no gate: the road crosses the wall once, straight
        let mut closed = land(400.0, |_| 0.0);
        set(
            &mut closed,
            |l, k| l.wall_mut()[k] = true,
            |q| (q.x - 260.0).abs() < 1.0,
        );
        let mut net = RoadNetwork::new(&closed, &[psi], &[]).unwrap();
        let c = connect(&mut net, &closed, &p, &occupied, b);
        assert!(c.reached);
        let over_wall = metres_over(&closed, &net.roads[c.roads[0]], |k| closed.wall()[k]);
        assert!(over_wall > 0.0 && over_wall <= 3.0, "{over_wall}");
    }

    #[test]
    fn a_cycle_is_added_ahead_of_the_building() {
        let land = land(400.0, |_| 0.0);
        let free = vec![false; land.grid().len()];
        let psi = DVec2::new(0.0, 200.0);
        let streets = vec![
            vec![psi, DVec2::new(400.0, 200.0)],
            vec![
                DVec2::new(100.0, 200.0),
                DVec2::new(100.0, 320.0),
                DVec2::new(400.0, 320.0),
            ],
        ];
        let mut net = RoadNetwork::new(&land, &[psi], &streets).unwrap();
        assert_eq!(net.roads.len(), 2);
        assert_eq!(net.roads[1].points, streets[1]);
        let c = connect(&mut net, &land, &params(), &free, DVec2::new(250.0, 250.0));
        assert!(c.reached && c.cycle && c.roads.len() == 2, "{c:?}");
        let first = &net.roads[c.roads[0]];
        let cycle = &net.roads[c.roads[1]];
        println!("first {:?}, cycle {:?}", first.points, cycle.points);
        assert!((first.points.last().unwrap().y - 200.0).abs() < 1e-9);
        assert!((cycle.points.last().unwrap().y - 320.0).abs() < 1e-9);
        assert!((length(cycle) - 70.0).abs() < 2.0);
        // without a road ahead there is no cycle
        let mut net = RoadNetwork::new(&land, &[psi], &streets[..1]).unwrap();
        let c = connect(&mut net, &land, &params(), &free, DVec2::new(250.0, 250.0));
        assert!(c.reached && !c.cycle && c.roads.len() == 1);
    }

    #[test]
    fn no_cycle_when_it_would_run_along_the_first_road() {
        // B at the end of a corridor 20 m wide, closed at its east end; the road ahead of B, beyond the end, can
        // only be reached back along the corridor, beside the first road
        let mut l = land(300.0, |_| 0.0);
        set(
            &mut l,
            |l, k| l.inside_mut()[k] = false,
            |q| {
                let strip_n = (160.0..=166.0).contains(&q.y) && (100.0..=266.0).contains(&q.x);
                let strip_s = (134.0..=140.0).contains(&q.y) && (100.0..=266.0).contains(&q.x);
                let end = (260.0..=266.0).contains(&q.x) && (134.0..=166.0).contains(&q.y);
                strip_n || strip_s || end
            },
        );
        let free = vec![false; l.grid().len()];
        let psi = [DVec2::new(0.0, 150.0), DVec2::new(286.0, 0.0)];
        let east = vec![DVec2::new(286.0, 0.0), DVec2::new(286.0, 300.0)];
        let p = RoadParams {
            cycle_max_length: 600.0,
            ..params()
        };
        let mut net = RoadNetwork::new(&l, &psi, &[east]).unwrap();
        let c = connect(&mut net, &l, &p, &free, DVec2::new(250.0, 150.0));
        assert!(c.reached, "{c:?}");
        let first = &net.roads[c.roads[0]];
        println!("first road {:?}; {c:?}", first.points);
        assert_eq!(*first.points.last().unwrap(), psi[0]);
        assert!(!c.cycle && c.roads.len() == 1);
    }

    #[test]
    fn an_enclosed_building_is_not_reached_and_bad_inputs_are_refused() {
        let mut l = land(200.0, |_| 0.0);
        // a ring outside the region around (150, 150)
        set(
            &mut l,
            |l, k| l.inside_mut()[k] = false,
            |q| {
                let d = q.distance(DVec2::new(150.0, 150.0));
                (20.0..=26.0).contains(&d)
            },
        );
        let free = vec![false; l.grid().len()];
        let (net, c) = first_road(
            &l,
            DVec2::new(0.0, 0.0),
            &params(),
            DVec2::new(150.0, 150.0),
        );
        assert_eq!(c, RoadConnection::default());
        assert!(net.roads.is_empty());
        assert_eq!(net.distance(DVec2::ZERO), f64::INFINITY);

        let bad = |r: Result<RoadNetwork, Error>| matches!(r, Err(e) if e.is_invalid_input());
        assert!(bad(RoadNetwork::new(&l, &[], &[])));
        assert!(bad(RoadNetwork::new(&l, &[DVec2::new(f64::NAN, 0.0)], &[])));
        assert!(bad(RoadNetwork::new(&l, &[DVec2::new(-100.0, 0.0)], &[])));
        assert!(bad(RoadNetwork::new(
            &l,
            &[DVec2::ZERO],
            &[vec![DVec2::ZERO, DVec2::new(f64::INFINITY, 1.0)]]
        )));
        // a connection point on a node outside the region snaps to the nearest one inside
        let q = DVec2::new(150.0, 127.0);
        let net = RoadNetwork::new(&l, &[q], &[]).unwrap();
        let snapped = net.connections()[0];
        assert!(l.inside()[l.grid().nearest_clamped(snapped)]);
        assert!(snapped.distance(q) <= 4.0, "{snapped}");

        let mut net = RoadNetwork::new(&l, &[DVec2::ZERO], &[]).unwrap();
        let nan = RoadParams {
            slope_weight: f64::NAN,
            ..params()
        };
        assert!(matches!(
            net.connect(&l, &nan, &free, DVec2::new(50.0, 50.0), 0.0),
            Err(e) if e.is_invalid_input()
        ));
        assert!(matches!(
            net.connect(&l, &params(), &free[1..], DVec2::new(50.0, 50.0), 0.0),
            Err(e) if e.is_invalid_input()
        ));
        assert!(matches!(
            net.connect(&l, &params(), &free, DVec2::new(f64::NAN, 50.0), 0.0),
            Err(e) if e.is_invalid_input()
        ));
        assert!(matches!(
            net.connect(&l, &params(), &free, DVec2::new(5000.0, 50.0), 0.0),
            Err(e) if e.is_invalid_input()
        ));
        // the move costs belong to the land the network was made on
        let mut other = l.clone();
        other.height_mut().iter_mut().for_each(|h| *h += 1.0);
        assert!(matches!(
            net.connect(&other, &params(), &free, DVec2::new(50.0, 50.0), 0.0),
            Err(e) if e.is_invalid_input()
        ));
        assert!(
            net.connect(&l, &params(), &free, DVec2::new(50.0, 50.0), 0.0)
                .unwrap()
                .reached
        );
    }

    /// A hilly 1 km² land at 2 m cells with a lake.
    fn hills() -> Land {
        let mut l = land(1000.0, |p| {
            let (x, y) = (p.x / 1000.0, p.y / 1000.0);
            40.0 * (3.1 * x).sin() * (2.3 * y + 0.4).cos()
                + 12.0 * (9.0 * x + 1.0).sin() * (7.0 * y).sin()
                + 3.0 * (31.0 * x).cos() * (27.0 * y + 2.0).sin()
        });
        set(
            &mut l,
            |l, k| l.water_mut()[k] = true,
            |q| q.distance(DVec2::new(700.0, 300.0)) < 80.0,
        );
        l
    }

    /// Building positions clustered around a centre, from a fixed sequence.
    fn village_homes(count: usize) -> Vec<DVec2> {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut homes: Vec<DVec2> = Vec::new();
        while homes.len() < count {
            let r = 260.0 * next().sqrt();
            let a = std::f64::consts::TAU * next();
            let q = DVec2::new(450.0, 550.0) + r * DVec2::new(a.cos(), a.sin());
            if q.distance(DVec2::new(700.0, 300.0)) > 95.0
                && homes.iter().all(|h| h.distance(q) > 18.0)
            {
                homes.push(q);
            }
        }
        homes
    }

    /// Connects a village of buildings one after the other, marking each house (10 × 8 m) as occupied.
    fn grow(land: &Land, p: &RoadParams, homes: &[DVec2]) -> (RoadNetwork, Vec<RoadConnection>) {
        let (net, out, _) = grow_timed(land, p, homes);
        (net, out)
    }

    /// [`grow`], with the (wall) time of each connection (s).
    fn grow_timed(
        land: &Land,
        p: &RoadParams,
        homes: &[DVec2],
    ) -> (RoadNetwork, Vec<RoadConnection>, Vec<f64>) {
        let psi = [DVec2::new(0.0, 500.0), DVec2::new(1000.0, 820.0)];
        let mut net = RoadNetwork::new(land, &psi, &[]).unwrap();
        let mut occupied = vec![false; land.grid().len()];
        let (mut out, mut times) = (Vec::new(), Vec::new());
        for &h in homes {
            let t = std::time::Instant::now();
            out.push(connect(&mut net, land, p, &occupied, h));
            times.push(t.elapsed().as_secs_f64());
            let g = land.grid();
            let (i0, j0) = (((h.x - 5.0) / CELL).ceil(), ((h.y - 4.0) / CELL).ceil());
            let (i1, j1) = (((h.x + 5.0) / CELL).floor(), ((h.y + 4.0) / CELL).floor());
            for j in j0.max(0.0) as usize..=(j1 as usize).min(g.ny - 1) {
                for i in i0.max(0.0) as usize..=(i1 as usize).min(g.nx - 1) {
                    occupied[g.index(i, j)] = true;
                }
            }
        }
        (net, out, times)
    }

    #[test]
    fn the_same_inputs_give_the_same_roads() {
        let l = hills();
        let homes = village_homes(15);
        let (a, ca) = grow(&l, &params(), &homes);
        let (b, cb) = grow(&l, &params(), &homes);
        assert_eq!(a.roads, b.roads);
        assert_eq!(ca, cb);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        let (c, cc) = pool.install(|| grow(&l, &params(), &homes));
        assert_eq!(a.roads, c.roads);
        assert_eq!(ca, cc);
        assert!(ca.iter().all(|c| c.reached));
        // every road keeps to the grade limit unless it says otherwise
        for c in &ca {
            for &r in &c.roads {
                let g = steepest(&l, &a.roads[r]);
                assert!(c.over_max_grade || g <= params().max_grade + 0.01, "{g}");
            }
        }
    }

    /// Time this thread has spent on a processor (s), when the system tells it (the machine may be shared).
    fn cpu_seconds() -> f64 {
        std::fs::read_to_string("/proc/thread-self/schedstat")
            .ok()
            .and_then(|s| s.split_whitespace().next()?.parse::<f64>().ok())
            .map_or(0.0, |ns| ns * 1e-9)
    }

    /// Timing of a 100-building village on 1 km² (501 × 501 nodes); run with `--ignored --nocapture`.
    #[test]
    #[ignore]
    fn timing_of_a_village() {
        let l = hills();
        let homes = village_homes(100);
        for radius in [1, 2, 3] {
            let p = RoadParams {
                mask_radius: radius,
                ..params()
            };
            let cpu = cpu_seconds();
            let (net, cs, times) = grow_timed(&l, &p, &homes);
            let cpu = cpu_seconds() - cpu;
            let wall: f64 = times.iter().sum();
            let mut sorted = times.clone();
            sorted.sort_by(f64::total_cmp);
            let total: f64 = net.roads.iter().map(length).sum();
            println!(
                "mask {radius}: {} connections, {:.3} s on the processor ({:.2} ms each); wall {wall:.3} s, \
                 first {:.1} ms, median {:.2} ms, slowest {:.1} ms; {} roads, {total:.0} m, {} cycles, \
                 {} over the grade, {} not reached",
                cs.len(),
                cpu,
                1000.0 * cpu / cs.len() as f64,
                1000.0 * times[0],
                1000.0 * sorted[sorted.len() / 2],
                1000.0 * sorted[sorted.len() - 1],
                net.roads.len(),
                cs.iter().filter(|c| c.cycle).count(),
                cs.iter().filter(|c| c.over_max_grade).count(),
                cs.iter().filter(|c| !c.reached).count()
            );
        }
    }
}
