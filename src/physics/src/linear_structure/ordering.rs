//! Reverse Cuthill-McKee ordering: a renumbering of a sparse symmetric matrix's rows that
//! makes its half-bandwidth small, so that the banded Cholesky of `banded` applies to a
//! structure numbered in any order (Cuthill and McKee, Proc. ACM 1969; the reversal, which
//! never widens the envelope, George and Liu, Computer Solution of Large Sparse Positive
//! Definite Systems, 1981, Sec. 4.3; the pseudo-peripheral start node, ibid., Sec. 4.3.2).

/// The adjacency of a symmetric pattern: `neighbours[i]` lists the j != i with a_ij != 0
/// in the pattern (explicit zeros included: they are where fill can go).
pub(crate) struct Graph {
    pub neighbours: Vec<Vec<usize>>,
}

impl Graph {
    /// The graph of `n` vertices with the edges `pairs` (each (i, j) once or twice, in
    /// any orientation; diagonal pairs ignored).
    pub fn new(n: usize, pairs: impl Iterator<Item = (usize, usize)>) -> Self {
        let mut neighbours = vec![Vec::new(); n];
        for (i, j) in pairs {
            if i != j {
                neighbours[i].push(j);
                neighbours[j].push(i);
            }
        }
        for list in &mut neighbours {
            list.sort_unstable();
            list.dedup();
        }
        Self { neighbours }
    }

    fn degree(&self, i: usize) -> usize {
        self.neighbours[i].len()
    }

    /// Breadth-first level structure from `root` over the vertices not `visited`: its
    /// depth and its last level. `mark` is all false on entry and on return, so that a
    /// search costs the size of its component, not of the graph.
    fn levels(&self, root: usize, visited: &[bool], mark: &mut [bool]) -> (usize, Vec<usize>) {
        let mut order = vec![root];
        mark[root] = true;
        let mut depth = 0;
        let mut level_start = 0;
        let mut last_level = vec![root];
        while level_start < order.len() {
            let level_end = order.len();
            for k in level_start..level_end {
                for &j in &self.neighbours[order[k]] {
                    if !visited[j] && !mark[j] {
                        mark[j] = true;
                        order.push(j);
                    }
                }
            }
            if order.len() > level_end {
                last_level = order[level_end..].to_vec();
                depth += 1;
            }
            level_start = level_end;
        }
        for &v in &order {
            mark[v] = false;
        }
        (depth, last_level)
    }

    /// A pseudo-peripheral vertex of `start`'s component: repeat "jump to a vertex of least
    /// degree in the deepest level" while the depth grows (George and Liu).
    fn peripheral(&self, start: usize, visited: &[bool], mark: &mut [bool]) -> usize {
        let mut root = start;
        let (mut depth, mut last) = self.levels(root, visited, mark);
        loop {
            let candidate = *last
                .iter()
                .min_by_key(|&&v| (self.degree(v), v))
                .expect("a level is never empty");
            let (d, l) = self.levels(candidate, visited, mark);
            if d <= depth {
                return root;
            }
            root = candidate;
            depth = d;
            last = l;
        }
    }
}

/// The reverse Cuthill-McKee order: `order[new] = old`. Each connected component is
/// numbered from a pseudo-peripheral vertex, neighbours by increasing degree (ties by
/// index, so that the order is deterministic).
pub(crate) fn reverse_cuthill_mckee(graph: &Graph) -> Vec<usize> {
    let n = graph.neighbours.len();
    let mut visited = vec![false; n];
    let mut mark = vec![false; n];
    let mut order = Vec::with_capacity(n);
    for start in 0..n {
        if visited[start] {
            continue;
        }
        let root = graph.peripheral(start, &visited, &mut mark);
        let first = order.len();
        order.push(root);
        visited[root] = true;
        let mut k = first;
        while k < order.len() {
            let mut next: Vec<usize> = graph.neighbours[order[k]]
                .iter()
                .copied()
                .filter(|&j| !visited[j])
                .collect();
            next.sort_unstable_by_key(|&j| (graph.degree(j), j));
            for j in next {
                visited[j] = true;
                order.push(j);
            }
            k += 1;
        }
    }
    order.reverse();
    order
}

/// The half-bandwidth max |p(i) - p(j)| of the edges under the numbering `position`
/// (`position[old] = new`).
pub(crate) fn half_bandwidth(graph: &Graph, position: &[usize]) -> usize {
    graph
        .neighbours
        .iter()
        .enumerate()
        .flat_map(|(i, list)| list.iter().map(move |&j| position[i].abs_diff(position[j])))
        .max()
        .unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 2D grid of nx x ny vertices numbered column-wise across the short side has
    /// half-bandwidth ny; a random shuffle of it has a band near n, and reverse
    /// Cuthill-McKee brings it back to at most ny + 1 (a level structure of a grid has
    /// levels of at most ny + 1 vertices along diagonals).
    #[test]
    fn a_shuffled_grid_gets_its_narrow_band_back() {
        let (nx, ny) = (40, 5);
        let id = |i: usize, j: usize| i * ny + j;
        let mut edges = Vec::new();
        for i in 0..nx {
            for j in 0..ny {
                if i + 1 < nx {
                    edges.push((id(i, j), id(i + 1, j)));
                }
                if j + 1 < ny {
                    edges.push((id(i, j), id(i, j + 1)));
                }
            }
        }
        let n = nx * ny;
        // A deterministic shuffle: multiplication by a unit modulo n.
        let shuffle: Vec<usize> = (0..n).map(|k| (k * 37) % n).collect();
        let graph = Graph::new(n, edges.iter().map(|&(a, b)| (shuffle[a], shuffle[b])));
        let identity: Vec<usize> = (0..n).collect();
        assert!(half_bandwidth(&graph, &identity) > n / 2);
        let order = reverse_cuthill_mckee(&graph);
        let mut position = vec![0; n];
        for (new, &old) in order.iter().enumerate() {
            position[old] = new;
        }
        let mut sorted = order.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, identity, "a permutation");
        let b = half_bandwidth(&graph, &position);
        assert!(b <= ny + 1, "half-bandwidth {b}");
    }

    #[test]
    fn disconnected_components_are_all_numbered() {
        let graph = Graph::new(5, [(0, 1), (3, 4)].into_iter());
        let mut order = reverse_cuthill_mckee(&graph);
        order.sort_unstable();
        assert_eq!(order, vec![0, 1, 2, 3, 4]);
        // 200,000 isolated vertices (a structure of independent springs): each search
        // costs its component, so this takes milliseconds, not n^2 = 4e10 steps.
        let n = 200_000;
        let isolated = Graph::new(n, std::iter::empty());
        let started = std::time::Instant::now();
        assert_eq!(reverse_cuthill_mckee(&isolated).len(), n);
        assert!(started.elapsed().as_secs_f64() < 5.0);
    }
}
