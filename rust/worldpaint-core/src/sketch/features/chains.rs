//! Linking edges that share vertices into polylines, split where the graph branches (shared by the silhouette
//! edges and the ridge forest).

/// The polylines of the graph of `edges` (pairs of vertex ids): each runs between two vertices where the graph
/// does not simply pass through (an end, or a vertex where three or more edges meet), through vertices with
/// exactly two edges; a closed loop of such vertices comes back to its first vertex. Deterministic: the result
/// depends on the set of edges only, not on their order.
pub(super) fn chains(edges: &[(u32, u32)]) -> Vec<Vec<u32>> {
    // half-edges sorted by their start: the edges at a vertex are one run
    let mut half: Vec<(u32, u32, u32)> = Vec::with_capacity(2 * edges.len());
    for (k, &(a, b)) in edges.iter().enumerate() {
        if a != b {
            half.push((a, b, k as u32));
            half.push((b, a, k as u32));
        }
    }
    half.sort_unstable();
    let at = |v: u32| -> &[(u32, u32, u32)] {
        let lo = half.partition_point(|h| h.0 < v);
        let hi = half.partition_point(|h| h.0 <= v);
        &half[lo..hi]
    };
    let mut used = vec![false; edges.len()];
    let mut out = Vec::new();
    let walk = |start: u32, first: (u32, u32, u32), used: &mut Vec<bool>| -> Vec<u32> {
        let mut line = vec![start];
        let (mut prev_edge, mut v) = (first.2, first.1);
        used[first.2 as usize] = true;
        loop {
            line.push(v);
            let next = at(v);
            if next.len() != 2 || v == start {
                break;
            }
            let Some(&(_, w, e)) = next.iter().find(|h| h.2 != prev_edge) else {
                break;
            };
            if used[e as usize] {
                break;
            }
            used[e as usize] = true;
            prev_edge = e;
            v = w;
        }
        line
    };
    // from every end and branching point, along each of its edges
    let mut k = 0;
    while k < half.len() {
        let v = half[k].0;
        let run = at(v);
        if run.len() != 2 {
            for &h in run {
                if !used[h.2 as usize] {
                    out.push(walk(v, h, &mut used));
                }
            }
        }
        k += run.len();
    }
    // what is left are loops of vertices with two edges each
    for &h in &half {
        if !used[h.2 as usize] {
            out.push(walk(h.0, h, &mut used));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_star_and_a_loop() {
        // a Y centred on 0 with arms 0-1-2, 0-3, 0-4-5, and a square 10-11-12-13
        let edges = [
            (1, 0),
            (2, 1),
            (0, 3),
            (4, 0),
            (4, 5),
            (10, 11),
            (12, 11),
            (13, 12),
            (10, 13),
        ];
        let mut lines = chains(&edges);
        lines.sort();
        assert_eq!(
            lines,
            vec![
                vec![0, 1, 2],
                vec![0, 3],
                vec![0, 4, 5],
                vec![10, 11, 12, 13, 10]
            ]
        );
        assert!(chains(&[]).is_empty());
    }
}
