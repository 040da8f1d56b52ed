//! The hull's support function by hill climbing over its vertex graph.
//!
//! The support point of a convex polytope in direction d, `argmax_v d·v`, is found by the
//! simplex method's argument: from any vertex, moving to a neighbour with a larger d·v ends at
//! the maximum, because a vertex none of whose neighbours is higher is a maximum over the
//! whole polytope (its edges span its tangent cone; the same holds for a vertex inside a
//! triangulated flat face, whose neighbours surround it). Starting from the best of the six
//! vertices extreme along the principal axes, a climb looks at a few dozen vertices instead
//! of all of them (Gilbert, Johnson & Keerthi 1988 use the same neighbour walk for GJK's
//! support; Cameron 1997, "Enhancing GJK", IEEE ICRA, names it hill climbing).
//!
//! Ties (a face perpendicular to d) are broken towards lower vertex numbers, so the result is
//! a fixed function of the hull and d; where several vertices share the largest d·v it may be
//! another of them than a linear scan's first.

use crate::math::V3;

/// Vertex neighbours of a triangulated hull, in compressed rows, and the climb's start
/// vertices.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct VertexGraph {
    /// `next[start[v]..start[v + 1]]` are the neighbours of vertex v, ascending.
    start: Vec<u32>,
    next: Vec<u32>,
    /// Vertices of least and greatest x, y and z.
    seeds: [u32; 6],
}

impl VertexGraph {
    /// The graph of the edges of `triangles` over `vertices`.
    pub fn new(vertices: &[V3], triangles: &[[u32; 3]]) -> VertexGraph {
        let mut edges: Vec<(u32, u32)> = triangles
            .iter()
            .flat_map(|&[a, b, c]| [(a, b), (b, a), (b, c), (c, b), (c, a), (a, c)])
            .collect();
        edges.sort_unstable();
        edges.dedup();
        let mut start = vec![0u32; vertices.len() + 1];
        for &(a, _) in &edges {
            start[a as usize + 1] += 1;
        }
        for v in 0..vertices.len() {
            start[v + 1] += start[v];
        }
        let next = edges.into_iter().map(|(_, b)| b).collect();
        let extreme = |key: &dyn Fn(V3) -> f64| {
            (0..vertices.len()).fold(0, |best, v| {
                if key(vertices[v]) > key(vertices[best]) {
                    v
                } else {
                    best
                }
            }) as u32
        };
        let seeds = [
            extreme(&|v| v.x),
            extreme(&|v| -v.x),
            extreme(&|v| v.y),
            extreme(&|v| -v.y),
            extreme(&|v| v.z),
            extreme(&|v| -v.z),
        ];
        VertexGraph { start, next, seeds }
    }

    /// Number of the vertex maximising `dir`·v.
    pub fn support_index(&self, vertices: &[V3], dir: V3) -> usize {
        let higher = |a: usize, da: f64, b: usize, db: f64| db > da || (db == da && b < a);
        let mut best = self.seeds[0] as usize;
        let mut best_dot = dir.dot(vertices[best]);
        for &s in &self.seeds[1..] {
            let d = dir.dot(vertices[s as usize]);
            if higher(best, best_dot, s as usize, d) {
                (best, best_dot) = (s as usize, d);
            }
        }
        loop {
            let from = best;
            let range = self.start[from] as usize..self.start[from + 1] as usize;
            for &n in &self.next[range] {
                let d = dir.dot(vertices[n as usize]);
                if higher(best, best_dot, n as usize, d) {
                    (best, best_dot) = (n as usize, d);
                }
            }
            if best == from {
                return best;
            }
        }
    }

    /// Neighbours of vertex `v`.
    pub fn neighbours(&self, v: usize) -> &[u32] {
        &self.next[self.start[v] as usize..self.start[v + 1] as usize]
    }
}
