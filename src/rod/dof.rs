//! The one place that knows where a node or an edge lives inside `q`.

/// Index of the x coordinate of node `i` (y and z follow).
#[inline]
pub const fn node(i: usize) -> usize {
    4 * i
}

/// Index of the twist angle `theta^j` of edge `j`.
#[inline]
pub const fn edge(j: usize) -> usize {
    4 * j + 3
}

/// Whether coordinate `k` is a twist angle.
#[inline]
pub const fn is_edge(k: usize) -> bool {
    k % 4 == 3
}

/// Number of generalised coordinates of a rod with `nodes` nodes (`nodes - 1` edges).
#[inline]
pub const fn count(nodes: usize) -> usize {
    4 * nodes - 1
}

/// Half-bandwidth of every Hessian assembled from node-centred stencils
/// (`x_{i-1}, theta^{i-1}, x_i, theta^i, x_{i+1}`): 11 consecutive coordinates.
pub const HALF_BANDWIDTH: usize = 10;

/// The 11 coordinates of the stencil centred on interior node `i`, in the order
/// `x_{i-1}, x_i, x_{i+1}, theta^{i-1}, theta^i`.
pub fn stencil(i: usize) -> [usize; 11] {
    let a = node(i - 1);
    let b = node(i);
    let c = node(i + 1);
    [
        a,
        a + 1,
        a + 2,
        b,
        b + 1,
        b + 2,
        c,
        c + 1,
        c + 2,
        edge(i - 1),
        edge(i),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn stencil_fits_in_band() {
        let s = stencil(5);
        let lo = *s.iter().min().unwrap();
        let hi = *s.iter().max().unwrap();
        assert_eq!(hi - lo, HALF_BANDWIDTH);
        assert_eq!(count(3), 11);
    }
}
