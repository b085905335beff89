//! A layered (Sugiyama) layout of one flat graph, in "rank" and "cross"
//! coordinates: ranks follow the edges' direction (down, or right), the
//! cross axis runs along each rank. [`crate::layout`] maps them to x and y
//! and tries several orientations and rank widths.
//!
//! The steps are the classic ones, as Graphviz `dot` takes them: cycles
//! broken by reversing the back edges of a depth-first search; ranks by
//! longest path, then each node moved to the median rank of its neighbours
//! within its slack, and ranks wider than a limit wrapped onto the next
//! ones (so that a fan of fifteen machines becomes a grid, not a row);
//! long edges cut by dummy nodes, an edge's label being a dummy the size of
//! the label in the middle rank (so labels never overlap nodes or other
//! labels, and sit beside their own edge); crossings reduced by median
//! sweeps with adjacent swaps, keeping the best order seen; cross positions
//! by repeated weighted averaging of neighbours, each rank solved exactly
//! for the order and spacing (pool-adjacent-violators); edges drawn
//! through their dummies with tangents along the rank axis, so that they
//! only cross between ranks and never pass through a node.

use crate::layout::Cubic;

/// Gap between an edge and its label.
pub(crate) const GAP: f64 = 6.0;
/// Space between two ranks.
const RANK_SEP: f64 = 20.0;
/// Space between two nodes of a rank.
const NODE_SEP: f64 = 18.0;
/// Space next to an edge's dummy.
const DUMMY_SEP: f64 = 8.0;
/// Space between the ends of two edges on a node's side, and the part of
/// the side they spread over.
const PORT_STEP: f64 = 7.0;
const PORT_SPAN: f64 = 0.8;
/// How far a self-loop reaches out of its node before its label.
const LOOP_REACH: f64 = 26.0;
/// How far a self-loop under its node reaches down, and how far from the
/// node's start it is.
const UNDER_REACH: f64 = 16.0;
const UNDER_INSET: f64 = 18.0;

/// A node: its size across ranks (`cross`) and along them (`along`).
#[derive(Debug, Clone, Copy)]
pub(crate) struct GNode {
    pub cross: f64,
    pub along: f64,
    /// Small round nodes: every edge meets them at the centre.
    pub round: bool,
    /// Whether the box may grow (for its edges' ends, or its self-loops'
    /// labels): not circles, nor composite states.
    pub stretch: bool,
}

/// An edge, with its label's size (cross, along) if labelled.
#[derive(Debug, Clone, Copy)]
pub(crate) struct GEdge {
    pub from: usize,
    pub to: usize,
    pub label: Option<(f64, f64)>,
}

/// A rectangle in (cross, along) coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct GRect {
    pub cross: f64,
    pub along: f64,
    pub w: f64,
    pub h: f64,
}

/// The result: nodes' boxes, edges' curves (from source to target) and
/// labels' boxes, and the number of crossings of the chosen order.
pub(crate) struct Placed {
    pub nodes: Vec<GRect>,
    pub paths: Vec<Vec<Cubic>>,
    pub labels: Vec<Option<GRect>>,
    pub crossings: usize,
}

/// A node of the layered graph.
#[derive(Debug, Clone)]
struct LNode {
    /// The graph's node, or `None` for a dummy.
    real: Option<usize>,
    /// Extent before and after its pass point on the cross axis.
    before: f64,
    after: f64,
    /// Extent along the rank axis.
    along: f64,
    rank: usize,
}

/// One edge's chain through the layers, from its layered source to its
/// layered target (reversed edges run backwards).
struct Chain {
    nodes: Vec<usize>,
    reversed: bool,
    label_at: Option<usize>,
}

/// Lays out a graph; `max_cross` bounds the summed size of the real nodes
/// of a rank (ranks wrap beyond it). Labels go beside their edge, or, with
/// `on_line`, centred on it (the renderer gives them a background).
pub(crate) fn layered(nodes: &[GNode], edges: &[GEdge], max_cross: Option<f64>, on_line: bool) -> Placed {
    let n = nodes.len();
    let proper: Vec<usize> =
        (0..edges.len()).filter(|&i| edges[i].from != edges[i].to && edges[i].from < n && edges[i].to < n).collect();
    let labelled = proper.iter().any(|&i| edges[i].label.is_some());
    let minlen = if labelled { 2 } else { 1 };

    // Cycles: reverse the back edges of a depth-first search.
    let reversed = back_edges(n, edges, &proper);
    let dir = |i: usize| if reversed[i] { (edges[i].to, edges[i].from) } else { (edges[i].from, edges[i].to) };
    // A box that many edges meet on one side grows along it, so that their
    // ends stay apart (a controller with thirty connections).
    let mut ends = vec![(0usize, 0usize); n];
    for &i in &proper {
        let (u, v) = dir(i);
        ends[u].0 += 1;
        ends[v].1 += 1;
    }
    let nodes: Vec<GNode> = nodes
        .iter()
        .zip(&ends)
        .map(|(g, &(o, i))| {
            let need = o.max(i) as f64 * PORT_STEP / PORT_SPAN;
            GNode { cross: if g.stretch { g.cross.max(need) } else { g.cross }, ..*g }
        })
        .collect();
    let nodes = &nodes[..];
    // Self-loops are drawn beside their node, which reserves room for them.
    let mut loops: Vec<Vec<usize>> = vec![Vec::new(); n];
    let mut reserve: Vec<(f64, f64)> = nodes.iter().map(|g| (g.cross, g.along)).collect();
    for (i, e) in edges.iter().enumerate() {
        if e.from == e.to && e.from < n {
            loops[e.from].push(i);
        }
    }
    // A node's only self-loop goes under it when nothing leaves from there
    // and its label fits under it (a wide composite state), else beside it.
    let mut under = vec![false; n];
    for (v, ls) in loops.iter().enumerate() {
        if ls.is_empty() {
            continue;
        }
        let (lw, lh) = edges[ls[0]].label.unwrap_or((0.0, 12.0));
        let leaves = proper.iter().any(|&i| dir(i).0 == v);
        if ls.len() == 1 && !leaves && !nodes[v].round && lw + UNDER_INSET + GAP + 12.0 <= nodes[v].cross {
            under[v] = true;
            reserve[v].1 += under_reach(lh) + lh.max(12.0) / 2.0 + 2.0;
            continue;
        }
        let widest = ls.iter().filter_map(|&i| edges[i].label).map(|l| l.0).fold(0.0, f64::max);
        let tall: f64 = ls.iter().map(|&i| edges[i].label.map_or(12.0, |l| l.1.max(12.0))).sum();
        reserve[v].0 += LOOP_REACH + GAP + widest;
        reserve[v].1 = reserve[v].1.max(tall);
    }
    let ranks = rank(n, &proper, &dir, minlen, max_cross.map(|m| (m, &reserve)));

    // The layered graph.
    let mut lnodes: Vec<LNode> = (0..n)
        .map(|v| {
            let half = nodes[v].cross / 2.0;
            LNode { real: Some(v), before: half, after: reserve[v].0 - half, along: reserve[v].1, rank: ranks[v] }
        })
        .collect();
    let mut chains: Vec<Option<Chain>> = (0..edges.len()).map(|_| None).collect();
    for &i in &proper {
        let (u, v) = dir(i);
        let (ru, rv) = (ranks[u], ranks[v]);
        let mid = ru + (rv - ru) / 2;
        let mut chain = vec![u];
        let mut label_at = None;
        for r in ru + 1..rv {
            let (before, after, along) = match edges[i].label {
                Some((w, h)) if r == mid => {
                    label_at = Some(lnodes.len());
                    if on_line {
                        (w / 2.0, w / 2.0, h)
                    } else {
                        (2.0, GAP + w, h)
                    }
                }
                _ => (1.0, 1.0, 0.0),
            };
            chain.push(lnodes.len());
            lnodes.push(LNode { real: None, before, after, along, rank: r });
        }
        chain.push(v);
        chains[i] = Some(Chain { nodes: chain, reversed: reversed[i], label_at });
    }
    let layers_n = lnodes.iter().map(|l| l.rank + 1).max().unwrap_or(0);
    let mut layers: Vec<Vec<usize>> = vec![Vec::new(); layers_n];
    // Links between consecutive layers (upper, lower).
    let mut links: Vec<(usize, usize)> = Vec::new();
    for c in chains.iter().flatten() {
        for w in c.nodes.windows(2) {
            links.push((w[0], w[1]));
        }
    }
    let mut up: Vec<Vec<usize>> = vec![Vec::new(); lnodes.len()];
    let mut down: Vec<Vec<usize>> = vec![Vec::new(); lnodes.len()];
    for &(a, b) in &links {
        down[a].push(b);
        up[b].push(a);
    }
    initial_order(&lnodes, &down, &mut layers);
    let crossings = order(&mut layers, &up, &down, lnodes.len());
    let pos = coordinates(&lnodes, &layers, &up, &down);

    // Ranks' bands along the rank axis.
    let mut band = Vec::with_capacity(layers_n);
    let mut at = 0.0;
    for layer in &layers {
        let thick = layer.iter().map(|&v| lnodes[v].along).fold(0.0, f64::max);
        band.push((at, thick));
        at += thick + RANK_SEP;
    }
    // A box with self-loops is stretched along the rank axis to the height
    // of their labels' stack, so that each loop meets it beside its label.
    let node_rect = |v: usize| {
        let (start, thick) = band[lnodes[v].rank];
        let g = &nodes[v];
        let room = reserve[v].1.max(g.along);
        let top = start + (thick - room) / 2.0;
        // Under-loops below the box; a box that cannot grow in the middle
        // of its loops' labels.
        let (top, along) = if under[v] {
            (top, g.along)
        } else if !g.stretch {
            (top + (room - g.along) / 2.0, g.along)
        } else {
            (top, room)
        };
        GRect { cross: pos[v] - g.cross / 2.0, along: top, w: g.cross, h: along }
    };
    let rects: Vec<GRect> = (0..n).map(node_rect).collect();

    // Ports: the edges leaving (entering) a node spread along its lower
    // (upper) side in the order of their other ends.
    let mut port: Vec<(f64, f64)> = vec![(0.0, 0.0); edges.len()];
    for v in 0..n {
        let spread = |list: &mut Vec<(f64, usize)>, out: bool, port: &mut Vec<(f64, f64)>| {
            list.sort_by(|a, b| a.0.total_cmp(&b.0));
            let k = list.len() as f64;
            let step = (nodes[v].cross * PORT_SPAN / k).min(14.0);
            for (j, &(_, i)) in list.iter().enumerate() {
                let x = pos[v] + (j as f64 - (k - 1.0) / 2.0) * step;
                if out {
                    port[i].0 = x;
                } else {
                    port[i].1 = x;
                }
            }
        };
        let mut outs = Vec::new();
        let mut ins = Vec::new();
        for (i, c) in chains.iter().enumerate() {
            let Some(c) = c else { continue };
            if c.nodes[0] == v {
                outs.push((pos[c.nodes[1]], i));
            }
            if c.nodes[c.nodes.len() - 1] == v {
                ins.push((pos[c.nodes[c.nodes.len() - 2]], i));
            }
        }
        spread(&mut outs, true, &mut port);
        spread(&mut ins, false, &mut port);
    }

    let mut paths = vec![Vec::new(); edges.len()];
    let mut labels = vec![None; edges.len()];
    for (i, c) in chains.iter().enumerate() {
        let Some(c) = c else { continue };
        let (u, v) = (c.nodes[0], c.nodes[c.nodes.len() - 1]);
        let (ru, rv) = (&rects[u], &rects[v]);
        // Points where the edge enters and leaves each rank's band.
        let mut pts: Vec<(f64, f64)> = Vec::new();
        let round_end = |r: &GRect| r.along + r.h / 2.0;
        let from_along = if nodes[u].round { round_end(ru) } else { ru.along + ru.h };
        pts.push((port[i].0, from_along));
        let (s, t) = band[lnodes[u].rank];
        pts.push((port[i].0, s + t));
        for &d in &c.nodes[1..c.nodes.len() - 1] {
            let (s, t) = band[lnodes[d].rank];
            pts.push((pos[d], s));
            pts.push((pos[d], s + t));
            if c.label_at == Some(d) {
                let (w, h) = edges[i].label.unwrap_or((0.0, 0.0));
                let cross = if on_line { pos[d] - w / 2.0 } else { pos[d] + GAP };
                labels[i] = Some(GRect { cross, along: s + (t - h) / 2.0, w, h });
            }
        }
        let (s, _) = band[lnodes[v].rank];
        pts.push((port[i].1, s));
        let to_along = if nodes[v].round { round_end(rv) } else { rv.along };
        pts.push((port[i].1, to_along));
        let mut curve = Vec::new();
        for (k, w) in pts.windows(2).enumerate() {
            let (a, b) = (w[0], w[1]);
            if (a.0 - b.0).abs() < 0.01 && (a.1 - b.1).abs() < 0.01 {
                continue;
            }
            // Odd windows go between two ranks: a curve with tangents
            // along the rank axis; even ones are straight inside a rank.
            curve.push(if k % 2 == 1 {
                let m = (b.1 - a.1) / 2.0;
                Cubic { p0: a, c1: (a.0, a.1 + m), c2: (b.0, b.1 - m), p3: b }
            } else {
                straight(a, b)
            });
        }
        if c.reversed {
            curve = curve.iter().rev().map(Cubic::reversed).collect();
        }
        paths[i] = curve;
    }
    // Self-loops, with their labels stacked beside the node.
    for (v, ls) in loops.iter().enumerate() {
        if ls.is_empty() {
            continue;
        }
        let r = rects[v];
        if under[v] {
            let i = ls[0];
            let bottom = r.along + r.h;
            let x = r.cross + UNDER_INSET;
            let apex = (x + 6.0, bottom + under_reach(edges[i].label.map_or(12.0, |l| l.1)));
            paths[i] = vec![
                Cubic { p0: (x - 6.0, bottom), c1: (x - 6.0, bottom + 10.0), c2: (apex.0 - 8.0, apex.1), p3: apex },
                Cubic { p0: apex, c1: (apex.0 + 8.0, apex.1), c2: (x + 18.0, bottom + 10.0), p3: (x + 18.0, bottom) },
            ];
            if let Some((w, h)) = edges[i].label {
                labels[i] = Some(GRect { cross: x + 18.0 + GAP, along: apex.1 - h / 2.0, w, h });
            }
            continue;
        }
        let right = r.cross + r.w;
        let tall: f64 = ls.iter().map(|&i| edges[i].label.map_or(12.0, |l| l.1.max(12.0))).sum();
        let mut y = r.along + r.h / 2.0 - tall / 2.0;
        for &i in ls {
            let h = edges[i].label.map_or(12.0, |l| l.1.max(12.0));
            // Each loop within its label's own stretch of the side: loops
            // never cross one another.
            let mid = y + h / 2.0;
            let a = (h / 3.0).min(5.0);
            let apex = (right + LOOP_REACH, mid);
            // On the node's side (which may not have been stretched).
            let side = |y: f64| y.clamp(r.along + 1.0, r.along + r.h - 1.0);
            let (p, q) = ((right, side(mid - a)), (right, side(mid + a)));
            paths[i] = vec![
                Cubic { p0: p, c1: (p.0 + 10.0, p.1), c2: (apex.0, mid - a), p3: apex },
                Cubic { p0: apex, c1: (apex.0, mid + a), c2: (q.0 + 10.0, q.1), p3: q },
            ];
            if let Some((w, lh)) = edges[i].label {
                labels[i] = Some(GRect { cross: apex.0 + GAP, along: y + (h - lh) / 2.0, w, h: lh });
            }
            y += h;
        }
    }
    Placed { nodes: rects, paths, labels, crossings }
}

/// How far under its node a self-loop's apex is: its label, centred on
/// it, must clear the node.
fn under_reach(label_h: f64) -> f64 {
    UNDER_REACH.max(4.0 + label_h / 2.0)
}

fn straight(a: (f64, f64), b: (f64, f64)) -> Cubic {
    let third = |t: f64| (a.0 + (b.0 - a.0) * t, a.1 + (b.1 - a.1) * t);
    Cubic { p0: a, c1: third(1.0 / 3.0), c2: third(2.0 / 3.0), p3: b }
}

/// Which edges to reverse so that the graph has no cycle: the back edges
/// of a depth-first search from the nodes in order (sources first).
fn back_edges(n: usize, edges: &[GEdge], proper: &[usize]) -> Vec<bool> {
    let mut out_edges: Vec<Vec<usize>> = vec![Vec::new(); n];
    let mut indeg = vec![0; n];
    for &i in proper {
        out_edges[edges[i].from].push(i);
        indeg[edges[i].to] += 1;
    }
    let mut reversed = vec![false; edges.len()];
    // 0 unvisited, 1 on the stack, 2 done.
    let mut state = vec![0u8; n];
    let mut roots: Vec<usize> = (0..n).filter(|&v| indeg[v] == 0).collect();
    roots.extend(0..n);
    for root in roots {
        if state[root] != 0 {
            continue;
        }
        let mut stack: Vec<(usize, usize)> = vec![(root, 0)];
        state[root] = 1;
        while let Some(&mut (v, ref mut k)) = stack.last_mut() {
            if let Some(&i) = out_edges[v].get(*k) {
                *k += 1;
                let w = edges[i].to;
                match state[w] {
                    0 => {
                        state[w] = 1;
                        stack.push((w, 0));
                    }
                    1 => reversed[i] = true,
                    _ => {}
                }
            } else {
                state[v] = 2;
                stack.pop();
            }
        }
    }
    reversed
}

/// Ranks: longest path, each node then moved to its neighbours' median
/// rank within its slack, then ranks wrapped at `wrap` (limit, reserved
/// node sizes).
fn rank(
    n: usize,
    proper: &[usize],
    dir: &dyn Fn(usize) -> (usize, usize),
    minlen: usize,
    wrap: Option<(f64, &Vec<(f64, f64)>)>,
) -> Vec<usize> {
    let mut preds: Vec<Vec<usize>> = vec![Vec::new(); n];
    let mut succs: Vec<Vec<usize>> = vec![Vec::new(); n];
    for &i in proper {
        let (u, v) = dir(i);
        succs[u].push(v);
        preds[v].push(u);
    }
    let topo = topological(n, &succs, &preds);
    let mut r = vec![0usize; n];
    for &v in &topo {
        for &p in &preds[v] {
            r[v] = r[v].max(r[p] + minlen);
        }
    }
    // Sources go down next to their successors.
    for &v in topo.iter().rev() {
        if preds[v].is_empty() && !succs[v].is_empty() {
            r[v] = succs[v].iter().map(|&s| r[s]).min().unwrap_or(minlen).saturating_sub(minlen);
        }
    }
    // Balance: each node to the median of its neighbours within its slack.
    for _ in 0..4 {
        for &v in &topo {
            if preds[v].is_empty() || succs[v].is_empty() {
                continue;
            }
            let lo = preds[v].iter().map(|&p| r[p] + minlen).max().unwrap_or(0);
            let hi = succs[v].iter().map(|&s| r[s].saturating_sub(minlen)).min().unwrap_or(lo);
            if hi <= lo {
                continue;
            }
            let mut around: Vec<usize> = preds[v].iter().chain(&succs[v]).map(|&x| r[x]).collect();
            around.sort();
            let m = around[around.len() / 2];
            // Keep the parity of ranks (labels sit on the odd ones).
            let m = m - (m.abs_diff(lo) % minlen);
            r[v] = m.clamp(lo, hi);
        }
    }
    if let Some((limit, sizes)) = wrap {
        // Top down: a rank over the limit sends its last nodes one rank
        // down, and their successors after them.
        let mut rank_at = 0;
        loop {
            let mut here: Vec<usize> = topo.iter().copied().filter(|&v| r[v] == rank_at).collect();
            if here.is_empty() && r.iter().all(|&x| x < rank_at) {
                break;
            }
            let mut used = 0.0;
            let mut moved = Vec::new();
            here.sort_by_key(|&v| std::cmp::Reverse(preds[v].len() + succs[v].len()));
            for (k, &v) in here.iter().enumerate() {
                let w = sizes[v].0 + NODE_SEP;
                if k > 0 && used + w > limit {
                    moved.push(v);
                } else {
                    used += w;
                }
            }
            for v in moved {
                r[v] += minlen;
            }
            for &v in &topo {
                for &p in &preds[v] {
                    if r[v] < r[p] + minlen {
                        r[v] = r[p] + minlen;
                    }
                }
            }
            rank_at += 1;
        }
    }
    let min = r.iter().copied().min().unwrap_or(0);
    r.iter().map(|x| x - min).collect()
}

/// A topological order (the graph is acyclic), nodes in index order when free.
fn topological(n: usize, succs: &[Vec<usize>], preds: &[Vec<usize>]) -> Vec<usize> {
    let mut indeg: Vec<usize> = preds.iter().map(Vec::len).collect();
    let mut ready: std::collections::BTreeSet<usize> = (0..n).filter(|&v| indeg[v] == 0).collect();
    let mut out = Vec::with_capacity(n);
    while let Some(v) = ready.pop_first() {
        out.push(v);
        for &s in &succs[v] {
            indeg[s] -= 1;
            if indeg[s] == 0 {
                ready.insert(s);
            }
        }
    }
    out
}

/// A first order: depth first from the top rank's nodes.
fn initial_order(lnodes: &[LNode], down: &[Vec<usize>], layers: &mut [Vec<usize>]) {
    let mut seen = vec![false; lnodes.len()];
    let mut by_rank: Vec<usize> = (0..lnodes.len()).collect();
    by_rank.sort_by_key(|&v| (lnodes[v].rank, v));
    for start in by_rank {
        if seen[start] {
            continue;
        }
        let mut stack = vec![start];
        while let Some(v) = stack.pop() {
            if seen[v] {
                continue;
            }
            seen[v] = true;
            layers[lnodes[v].rank].push(v);
            for &w in down[v].iter().rev() {
                if !seen[w] {
                    stack.push(w);
                }
            }
        }
    }
}

/// Crossings between a layer and the next, given positions.
fn crossings_between(upper: &[usize], down: &[Vec<usize>], at: &[usize]) -> usize {
    let mut ends: Vec<(usize, usize)> = Vec::new();
    for (i, &u) in upper.iter().enumerate() {
        for &w in &down[u] {
            ends.push((i, at[w]));
        }
    }
    let mut c = 0;
    for (k, a) in ends.iter().enumerate() {
        for b in &ends[k + 1..] {
            if (a.0 < b.0 && a.1 > b.1) || (a.0 > b.0 && a.1 < b.1) {
                c += 1;
            }
        }
    }
    c
}

fn total_crossings(layers: &[Vec<usize>], down: &[Vec<usize>], at: &[usize]) -> usize {
    layers.windows(2).map(|w| crossings_between(&w[0], down, at)).sum()
}

fn positions(layers: &[Vec<usize>], at: &mut [usize]) {
    for l in layers {
        for (i, &v) in l.iter().enumerate() {
            at[v] = i;
        }
    }
}

/// Median sweeps with adjacent swaps; keeps the order with the fewest
/// crossings and returns their number.
fn order(layers: &mut [Vec<usize>], up: &[Vec<usize>], down: &[Vec<usize>], count: usize) -> usize {
    let mut at = vec![0usize; count];
    positions(layers, &mut at);
    let mut best = layers.to_vec();
    let mut best_c = total_crossings(layers, down, &at);
    for iter in 0..16 {
        if best_c == 0 {
            break;
        }
        let downward = iter % 2 == 0;
        let range: Vec<usize> =
            if downward { (1..layers.len()).collect() } else { (0..layers.len().saturating_sub(1)).rev().collect() };
        for l in range {
            let nb = if downward { up } else { down };
            let mut keyed: Vec<(f64, usize)> = layers[l]
                .iter()
                .enumerate()
                .map(|(i, &v)| {
                    let mut ps: Vec<usize> = nb[v].iter().map(|&w| at[w]).collect();
                    ps.sort();
                    let key = match ps.len() {
                        0 => i as f64,
                        k if k % 2 == 1 => ps[k / 2] as f64,
                        k => (ps[k / 2 - 1] + ps[k / 2]) as f64 / 2.0,
                    };
                    (key, v)
                })
                .collect();
            keyed.sort_by(|a, b| a.0.total_cmp(&b.0));
            layers[l] = keyed.into_iter().map(|(_, v)| v).collect();
            for (i, &v) in layers[l].iter().enumerate() {
                at[v] = i;
            }
        }
        transpose(layers, up, down, &mut at);
        let c = total_crossings(layers, down, &at);
        if c < best_c {
            best_c = c;
            best = layers.to_vec();
        }
    }
    layers.clone_from_slice(&best);
    best_c
}

/// Swaps neighbours of a layer while that lowers the crossings with the
/// layers above and below.
fn transpose(layers: &mut [Vec<usize>], up: &[Vec<usize>], down: &[Vec<usize>], at: &mut [usize]) {
    let pair = |a: usize, b: usize, at: &[usize]| -> usize {
        // Crossings between a's and b's links when a is left of b.
        let mut c = 0;
        for nb in [up, down] {
            for &x in &nb[a] {
                for &y in &nb[b] {
                    if at[x] > at[y] {
                        c += 1;
                    }
                }
            }
        }
        c
    };
    for _ in 0..4 {
        let mut improved = false;
        for layer in layers.iter_mut() {
            for i in 0..layer.len().saturating_sub(1) {
                let (a, b) = (layer[i], layer[i + 1]);
                if pair(a, b, at) > pair(b, a, at) {
                    layer.swap(i, i + 1);
                    at[a] = i + 1;
                    at[b] = i;
                    improved = true;
                }
            }
        }
        if !improved {
            break;
        }
    }
}

/// Cross positions: each node near the weighted mean of its neighbours,
/// each layer solved exactly for its order and spacing.
fn coordinates(lnodes: &[LNode], layers: &[Vec<usize>], up: &[Vec<usize>], down: &[Vec<usize>]) -> Vec<f64> {
    let mut pos = vec![0.0; lnodes.len()];
    let sep = |a: usize, b: usize| {
        let s = if lnodes[a].real.is_some() && lnodes[b].real.is_some() { NODE_SEP } else { DUMMY_SEP };
        lnodes[a].after + s + lnodes[b].before
    };
    for l in layers {
        let mut x = 0.0;
        for (i, &v) in l.iter().enumerate() {
            if i > 0 {
                x += sep(l[i - 1], v);
            }
            pos[v] = x;
        }
    }
    // Straight long edges matter most (dot's weights: 1, 2, 8).
    let weight = |a: usize, b: usize| match (lnodes[a].real.is_some(), lnodes[b].real.is_some()) {
        (true, true) => 1.0,
        (false, false) => 8.0,
        _ => 2.0,
    };
    for iter in 0..24 {
        let order: Vec<usize> =
            if iter % 2 == 0 { (0..layers.len()).collect() } else { (0..layers.len()).rev().collect() };
        for l in order {
            let layer = &layers[l];
            let want: Vec<(f64, f64)> = layer
                .iter()
                .map(|&v| {
                    let (mut s, mut w) = (0.0, 0.0);
                    for &x in up[v].iter().chain(&down[v]) {
                        let k = weight(v, x);
                        s += k * pos[x];
                        w += k;
                    }
                    if w == 0.0 {
                        (pos[v], 0.01)
                    } else {
                        (s / w, w)
                    }
                })
                .collect();
            let offsets: Vec<f64> = layer
                .iter()
                .enumerate()
                .scan(0.0, |acc, (i, &v)| {
                    if i > 0 {
                        *acc += sep(layer[i - 1], v);
                    }
                    Some(*acc)
                })
                .collect();
            let solved = isotonic(&want.iter().zip(&offsets).map(|((d, w), o)| (d - o, *w)).collect::<Vec<_>>());
            for (i, &v) in layer.iter().enumerate() {
                pos[v] = solved[i] + offsets[i];
            }
        }
    }
    let min = layers.iter().flat_map(|l| l.iter().map(|&v| pos[v] - lnodes[v].before)).fold(f64::MAX, f64::min);
    pos.iter().map(|p| p - min).collect()
}

/// Weighted least squares non-decreasing fit (pool adjacent violators).
fn isotonic(values: &[(f64, f64)]) -> Vec<f64> {
    // Blocks of (mean, weight, count).
    let mut blocks: Vec<(f64, f64, usize)> = Vec::new();
    for &(v, w) in values {
        blocks.push((v, w, 1));
        while blocks.len() > 1 {
            let (m2, w2, c2) = blocks[blocks.len() - 1];
            let (m1, w1, c1) = blocks[blocks.len() - 2];
            if m1 <= m2 {
                break;
            }
            blocks.pop();
            let last = blocks.len() - 1;
            blocks[last] = ((m1 * w1 + m2 * w2) / (w1 + w2), w1 + w2, c1 + c2);
        }
    }
    blocks.iter().flat_map(|&(m, _, c)| std::iter::repeat_n(m, c)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small deterministic generator (no dependency).
    struct Lcg(u64);
    impl Lcg {
        fn next(&mut self, n: usize) -> usize {
            self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((self.0 >> 33) % n as u64) as usize
        }
    }

    fn overlap(a: &GRect, b: &GRect) -> bool {
        a.cross < b.cross + b.w - 0.01
            && b.cross < a.cross + a.w - 0.01
            && a.along < b.along + b.h - 0.01
            && b.along < a.along + a.h - 0.01
    }

    /// Random graphs with cycles, self-loops, parallel edges, round nodes
    /// and labels, wrapped or not, labels on or beside their line: every
    /// edge is drawn from its source to its target, and no two boxes
    /// (nodes, labels) overlap.
    #[test]
    fn random_graphs_are_laid_out_without_overlaps() {
        let mut g = Lcg(7);
        for case in 0..300 {
            let n = 1 + g.next(14);
            let nodes: Vec<GNode> = (0..n)
                .map(|_| {
                    let round = g.next(4) == 0;
                    let (w, h) =
                        if round { (16.0, 16.0) } else { (40.0 + g.next(200) as f64, 30.0 + g.next(60) as f64) };
                    GNode { cross: w, along: h, round, stretch: !round && g.next(5) > 0 }
                })
                .collect();
            let m = g.next(3 * n + 2);
            let edges: Vec<GEdge> = (0..m)
                .map(|_| GEdge {
                    from: g.next(n),
                    to: g.next(n),
                    label: (g.next(3) > 0).then(|| (20.0 + g.next(250) as f64, 16.0 * (1 + g.next(3)) as f64)),
                })
                .collect();
            let limit = [None, Some(200.0), Some(500.0)][case % 3];
            let p = layered(&nodes, &edges, limit, case % 2 == 0);
            assert_eq!(p.nodes.len(), n);
            let boxes: Vec<GRect> = p.nodes.iter().chain(p.labels.iter().flatten()).copied().collect();
            for (i, a) in boxes.iter().enumerate() {
                for b in &boxes[i + 1..] {
                    assert!(!overlap(a, b), "case {case}: {a:?} overlaps {b:?}");
                }
            }
            for (i, e) in edges.iter().enumerate() {
                let path = &p.paths[i];
                assert!(!path.is_empty(), "case {case}: edge {i} is not drawn");
                assert_eq!(e.label.is_some(), p.labels[i].is_some(), "case {case}: edge {i}'s label");
                // From the source's box to the target's (round nodes: their centre).
                let near = |pt: (f64, f64), r: &GRect| {
                    pt.0 >= r.cross - 0.5
                        && pt.0 <= r.cross + r.w + 0.5
                        && pt.1 >= r.along - 0.5
                        && pt.1 <= r.along + r.h + 0.5
                };
                assert!(
                    near(path[0].p0, &p.nodes[e.from]),
                    "case {case}: edge {i} {e:?} starts away from its source: {path:?} {:?} {:?}",
                    p.nodes[e.from],
                    p.nodes[e.to]
                );
                assert!(
                    near(path[path.len() - 1].p3, &p.nodes[e.to]),
                    "case {case}: edge {i} ends away from its target"
                );
                // Through no other node.
                for (k, r) in p.nodes.iter().enumerate() {
                    if k == e.from || k == e.to {
                        continue;
                    }
                    for c in path {
                        for t in 0..=16 {
                            let q = c.at(t as f64 / 16.0);
                            let inside = q.0 > r.cross + 0.5
                                && q.0 < r.cross + r.w - 0.5
                                && q.1 > r.along + 0.5
                                && q.1 < r.along + r.h - 0.5;
                            assert!(!inside, "case {case}: edge {i} passes through node {k}");
                        }
                    }
                }
            }
        }
    }
}
