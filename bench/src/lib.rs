//! What the side-by-side benchmarks of this crate share (`src/main.rs`, `src/bin/*`).

/// The median of `v` (sorts it; the upper middle value of an even count).
///
/// # Panics
/// When `v` is empty.
pub fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}
