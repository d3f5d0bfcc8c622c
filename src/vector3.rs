//! Small helpers on 3-vectors (`[f64; 3]`): the few operations the mesh, element and contact
//! code need, in one place instead of a private copy per module. Plain arrays rather than a
//! linear-algebra crate's type because nodes are stored as `[f64; 3]` everywhere; each
//! function is written out component by component, so results are bit-for-bit what the
//! copies it replaced computed.

/// a + b.
pub fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// a - b.
pub fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// s a.
pub fn scale(s: f64, a: [f64; 3]) -> [f64; 3] {
    [s * a[0], s * a[1], s * a[2]]
}

/// a . b.
pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// a x b (right-handed).
pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Euclidean length |a|.
pub fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

/// a / |a|, or `None` when the length is zero or not finite (no direction to give).
pub fn normalize(a: [f64; 3]) -> Option<[f64; 3]> {
    let length = norm(a);
    (length > 0.0 && length.is_finite()).then(|| scale(1.0 / length, a))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identities_on_exact_values() {
        let (a, b) = ([1.0, 2.0, 3.0], [-4.0, 0.5, 2.0]);
        assert_eq!(add(a, b), [-3.0, 2.5, 5.0]);
        assert_eq!(sub(a, b), [5.0, 1.5, 1.0]);
        assert_eq!(scale(2.0, a), [2.0, 4.0, 6.0]);
        assert_eq!(dot(a, b), 3.0);
        let c = cross(a, b);
        assert_eq!((dot(c, a), dot(c, b)), (0.0, 0.0));
        assert_eq!(cross([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]), [0.0, 0.0, 1.0]);
        assert_eq!(norm([3.0, 4.0, 12.0]), 13.0);
        assert_eq!(normalize([0.0, -2.0, 0.0]), Some([0.0, -1.0, 0.0]));
        assert_eq!(normalize([0.0; 3]), None);
        assert_eq!(normalize([f64::INFINITY, 0.0, 0.0]), None);
    }
}
