//! Worn-surface interpolation: exactness, locality, smoothness, positivity, serde.

mod common;

use approx::assert_relative_eq;
use common::*;
use contact::{CircularProfile, SurfaceProfile};
use proptest::prelude::*;
use std::f64::consts::TAU;
use wear::{Side, WornJoint, WornProfile};

fn dented(cells: usize, k: usize, depth: f64) -> WornProfile {
    let mut h = vec![0.0; cells];
    h[k] = depth;
    WornProfile::from_depths(Side::Bearing, R_BEARING, h).unwrap()
}

#[test]
fn unworn_profile_is_the_circle() {
    let joint = joint(1000);
    for i in -20..=20 {
        let angle = i as f64 * 0.77;
        assert_eq!(
            joint.bearing().sample(angle),
            CircularProfile::new(R_BEARING).sample(angle)
        );
        assert_eq!(
            joint.pin().sample(angle),
            CircularProfile::new(R_PIN).sample(angle)
        );
    }
}

#[test]
fn dent_is_local_and_signed_by_side() {
    let cells = 360;
    let k = 90;
    let p = dented(cells, k, 1e-5);
    let dtheta = TAU / cells as f64;
    let centre = p.cell_center(k);
    // Inside the dent the bearing radius grows by up to h/2 (B-spline peak: 2/3 of a spike).
    assert_relative_eq!(
        p.sample(centre).radius - R_BEARING,
        0.5 * 1e-5 * 2.0 / 3.0,
        max_relative = 1e-9
    );
    // Support: ±2 cells from the dent's centre, exactly circular beyond.
    for i in 0..cells * 8 {
        let angle = i as f64 * dtheta / 8.0;
        let off = ((angle - centre + TAU / 2.0).rem_euclid(TAU) - TAU / 2.0).abs();
        let s = p.sample(angle);
        if off >= 2.0 * dtheta {
            assert_eq!(s.radius, R_BEARING, "angle {angle}");
            assert_eq!(s.slope, 0.0);
        } else if off < 1.9 * dtheta {
            assert!(s.radius > R_BEARING);
        }
    }
    // The same depths on a pin shrink it.
    let pin = WornProfile::from_depths(Side::Pin, R_PIN, p.depth().to_vec()).unwrap();
    assert_relative_eq!(
        pin.sample(centre).radius - R_PIN,
        -(p.sample(centre).radius - R_BEARING)
    );
}

fn rough(cells: usize) -> WornProfile {
    // Non-smooth data with large values at both ends of the grid (tests the 0/2π seam).
    let h = (0..cells)
        .map(|k| 1e-5 * (((k * 7919) % 13) as f64) / 13.0)
        .collect();
    WornProfile::from_depths(Side::Pin, R_PIN, h).unwrap()
}

#[test]
fn continuous_value_and_slope_across_seam_and_cell_edges() {
    let p = rough(100);
    let dtheta = p.cell_width();
    let eps = 1e-9;
    // Cell edges of the spline segments sit at cell centres; check those, the cell
    // boundaries and the seam, approached from both sides and across 2π aliases.
    for k in 0..100 {
        for edge in [k as f64 * dtheta, p.cell_center(k)] {
            let (l, r) = (p.sample(edge - eps), p.sample(edge + eps));
            assert!((l.radius - r.radius).abs() < 1e-12, "value jump at {edge}");
            assert!((l.slope - r.slope).abs() < 1e-7, "slope jump at {edge}");
        }
    }
    for a in [0.0, 1.234] {
        let s = p.sample(a);
        assert_relative_eq!(p.sample(a + TAU).radius, s.radius, max_relative = 1e-14);
        assert_relative_eq!(p.sample(a - 3.0 * TAU).slope, s.slope, max_relative = 1e-9);
    }
    let (l, r) = (p.sample(-eps), p.sample(eps));
    assert!((l.radius - r.radius).abs() < 1e-12);
    assert!((l.slope - r.slope).abs() < 1e-7);
}

#[test]
fn slope_is_the_derivative_of_radius() {
    let p = rough(1000);
    let h = 1e-6;
    for i in 0..2000 {
        let a = i as f64 * TAU / 2000.0 + 1e-4;
        let fd = (p.sample(a + h).radius - p.sample(a - h).radius) / (2.0 * h);
        let exact = p.sample(a).slope;
        assert!(
            (fd - exact).abs() < 1e-6 * exact.abs().max(1e-4),
            "at {a}: fd {fd} vs {exact}"
        );
    }
}

proptest! {
    /// Interpolated wear lies between 0 and the largest cell, so it is never negative and
    /// the local clearance never falls below c0.
    #[test]
    fn interpolated_depth_is_bounded(
        depths in prop::collection::vec(0.0f64..1e-4, 1..64),
        angle in -20.0f64..20.0,
    ) {
        let max = depths.iter().copied().fold(0.0, f64::max);
        let bearing = WornProfile::from_depths(Side::Bearing, R_BEARING, depths.clone()).unwrap();
        let pin = WornProfile::from_depths(Side::Pin, R_PIN, depths).unwrap();
        let (h, _) = bearing.wear_depth(angle);
        prop_assert!(h >= 0.0 && h <= max * (1.0 + 1e-12));
        let joint = WornJoint::from_profiles(K_D, WIDTH, bearing, pin).unwrap();
        prop_assert!(joint.local_clearance(angle, 0.3 - angle) >= CLEARANCE * (1.0 - 1e-12));
    }
}

#[test]
fn spline_conserves_volume() {
    let p = rough(200);
    let n = 20_000;
    let integral: f64 = (0..n)
        .map(|i| p.wear_depth((i as f64 + 0.5) * TAU / n as f64).0)
        .sum::<f64>()
        * TAU
        / n as f64;
    let cells: f64 = p.depth().iter().sum::<f64>() * p.cell_width();
    assert_relative_eq!(integral, cells, max_relative = 1e-6);
}

#[test]
fn worn_joint_round_trips_through_json() {
    let mut joint = joint(1000);
    let s = loaded(3000.0, 0.05, 1e-5, 1.0, 2.0);
    let mut stage = joint.start_stage();
    stage.accumulate_step(&s, &s, 0.1).unwrap();
    joint.apply(&stage, 20_000.0).unwrap();
    let json = serde_json::to_string(&joint).unwrap();
    let back: WornJoint = serde_json::from_str(&json).unwrap();
    // serde_json's default float parser may be off by one ulp (exact needs its
    // `float_roundtrip` feature), so compare to 1e-15 rather than bit for bit.
    assert_eq!(back.wear_coefficient(), joint.wear_coefficient());
    assert_eq!(back.hinge_width(), joint.hinge_width());
    for (b, j) in [(back.pin(), joint.pin()), (back.bearing(), joint.bearing())] {
        assert_eq!(
            (b.side(), b.nominal_radius(), b.cells()),
            (j.side(), j.nominal_radius(), j.cells())
        );
        for (x, y) in b.depth().iter().zip(j.depth()) {
            assert_relative_eq!(*x, *y, max_relative = 1e-15);
        }
        for a in [0.5, 1.0, 2.0, 6.0] {
            assert_relative_eq!(b.sample(a).radius, j.sample(a).radius, max_relative = 1e-15);
            assert_relative_eq!(
                b.sample(a).slope,
                j.sample(a).slope,
                max_relative = 1e-12,
                epsilon = 1e-18
            );
        }
    }
    assert!(joint.pin().peak().depth > 0.0 && joint.bearing().peak().depth > 0.0);
    // Deserialization validates: a negative depth is refused.
    let bad = json.replacen("\"depth\":[0.0", "\"depth\":[-1.0", 1);
    assert_ne!(bad, json);
    let err = serde_json::from_str::<WornJoint>(&bad)
        .unwrap_err()
        .to_string();
    assert!(err.contains("depth[0] = -1"), "{err}");
}

#[test]
fn concentrated_ranges_merge_through_zero() {
    let mut h = vec![0.0; 360];
    for k in (350..360).chain(0..5) {
        h[k] = 2e-6;
    }
    h[90..100].fill(1e-6);
    let p = WornProfile::from_depths(Side::Bearing, R_BEARING, h).unwrap();
    let r = p.concentrated_ranges(0.4);
    assert_eq!(r.len(), 2);
    assert_relative_eq!(r[0].start.to_degrees(), 350.0, epsilon = 1e-9);
    assert_relative_eq!(r[0].end.to_degrees(), 365.0, epsilon = 1e-9);
    // Reports show the wrapped range with both ends in [0°, 360°).
    let [start, end] = r[0].degrees();
    assert_relative_eq!(start, 350.0, epsilon = 1e-9);
    assert_relative_eq!(end, 5.0, epsilon = 1e-9);
    assert_relative_eq!(r[1].start.to_degrees(), 90.0, epsilon = 1e-9);
    assert_eq!(r[1].peak, 1e-6);
}

/// 360 cells of uneven wear, 0–20 µm.
fn wavy_depths() -> Vec<f64> {
    (0..360)
        .map(|k| 1e-5 * (1.0 + (0.37 * k as f64).sin() * (0.05 * k as f64).cos()))
        .collect()
}

/// The sector bounds the foundation contact skips by hold every sample of the spline inside
/// the sector, and are exact for an unworn surface.
#[test]
fn radius_bounds_between_hold_every_sample() {
    use contact::SurfaceProfile;
    use wear::{Side, WornProfile};
    let depths = wavy_depths();
    for side in [Side::Bearing, Side::Pin] {
        let profile = WornProfile::from_depths(side, 0.05, depths.clone()).unwrap();
        for (start, width) in [
            (0.0, 0.1),
            (6.2, 0.2),
            (-0.3, 0.05),
            (1.0, 6.5),
            (3.0, 0.001),
        ] {
            let (low, high) = profile.radius_bounds_between(start, start + width).unwrap();
            for k in 0..=200 {
                let r = profile.sample(start + width * k as f64 / 200.0).radius;
                assert!(
                    low <= r && r <= high,
                    "{side:?} [{start}, +{width}]: {r} not in [{low}, {high}]"
                );
            }
        }
    }
    let round = WornProfile::new(Side::Bearing, 0.05, 100).unwrap();
    assert_eq!(round.radius_bounds_between(1.0, 2.0), Some((0.05, 0.05)));
}

/// The slope bound the foundation's overlap memory relies on holds at every sample and is
/// tight: the spline's steepest slope found on a fine scan reaches most of it (measured:
/// printed), and an unworn surface has none.
#[test]
fn slope_bound_holds_every_sample_and_is_tight() {
    use contact::SurfaceProfile;
    use wear::{Side, WornProfile};
    let depths = wavy_depths();
    for side in [Side::Bearing, Side::Pin] {
        let profile = WornProfile::from_depths(side, 0.05, depths.clone()).unwrap();
        let bound = profile.slope_bound().unwrap();
        let steepest = (0..360 * 64)
            .map(|k| {
                profile
                    .sample(k as f64 * std::f64::consts::TAU / (360.0 * 64.0))
                    .slope
                    .abs()
            })
            .fold(0.0, f64::max);
        eprintln!("{side:?}: steepest slope {steepest:.4e} m/rad, bound {bound:.4e}");
        assert!(
            steepest <= bound,
            "{side:?}: {steepest} above the bound {bound}"
        );
        assert!(
            steepest >= 0.7 * bound,
            "{side:?}: bound {bound} loose ({steepest})"
        );
    }
    let round = WornProfile::new(Side::Bearing, 0.05, 100).unwrap();
    assert_eq!(round.slope_bound(), Some(0.0));
}
