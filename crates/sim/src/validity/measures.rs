//! The measures of a worn geometry's validity and their limits (see [`super`]).

use contact::{ContactDiagnostics, ContactModel, ValidityMeasure};
use serde::Serialize;

/// Median elastic share of the per-cycle force peaks below which a response's forces are
/// mostly the damping term of the law, not loads the surfaces carry: flagged, not results.
pub const MIN_ELASTIC_SHARE: f64 = 0.5;

/// The limits a run's worn geometry must stay within.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ValidityLimits {
    /// Largest `|R_i' − R_j'|/|e|` at a loaded frame.
    pub slope_ratio: f64,
    /// Largest `(R_j'' − R_i'')/c` at a loaded frame.
    pub conformity_ratio: f64,
    /// Largest fraction of penetrating frames (δ > 1 % of c) that carry no force.
    pub unloaded_fraction: f64,
    /// Largest `|max(overlap, 0) − max(δ, 0)| / c` over the checked frames.
    pub overlap_error: f64,
    /// Largest fraction of the checked frames where the outlines overlap but `δ < 0`.
    pub missed_contact_fraction: f64,
    /// Foundation: largest overlap of the outlines over the nominal clearance.
    pub overlap_ratio: f64,
    /// Foundation: largest estimated relative error of the normal load from the grid's
    /// resolution of the contact zones, at frames overlapping by more than 1 % of the clearance.
    pub resolution_error: f64,
    /// Thin gap: largest share of the overlap its neglected terms may reach, at frames
    /// overlapping by more than 1 % of the clearance.
    pub neglected_terms: f64,
    /// Smallest median elastic share `F_e/F_n` of the per-cycle force peaks after the
    /// start-up window: below it the peaks are mostly the law's damping term.
    pub elastic_share: f64,
}

impl Default for ValidityLimits {
    fn default() -> Self {
        Self {
            slope_ratio: 0.3,
            conformity_ratio: 1.0,
            unloaded_fraction: 0.01,
            overlap_error: 0.1,
            missed_contact_fraction: 0.01,
            overlap_ratio: 0.2,
            resolution_error: 0.02,
            neglected_terms: 0.01,
            elastic_share: MIN_ELASTIC_SHARE,
        }
    }
}

/// What was measured for one joint in one response run, against the limits.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Validity {
    /// The contact model measured (its name: `foundation`, `line-of-centres`).
    pub model: &'static str,
    /// The measures the model is judged by, in the order of their verdicts
    /// ([`ContactModel::validity_measures`]).
    #[serde(skip)]
    pub measures: &'static [ValidityMeasure],
    /// Every measure within its limit.
    pub inside: bool,
    /// One sentence per measure beyond its limit.
    pub reasons: Vec<String>,
    /// Frames with the pin loaded (`F_n > 0`).
    pub loaded_frames: usize,
    /// Largest `|R_i' − R_j'|/|e|` at a loaded frame.
    pub max_slope_ratio: f64,
    /// Largest `(R_j'' − R_i'')/c` at a loaded frame.
    pub max_conformity_ratio: f64,
    /// Frames with `δ` above 1 % of the clearance.
    pub penetrating_frames: usize,
    /// Of those, frames without force.
    pub unloaded_penetrating_frames: usize,
    /// Frames where the outline overlap was measured.
    pub overlap_frames: usize,
    /// Largest `|max(overlap, 0) − max(δ, 0)|` over those frames, m.
    pub max_overlap_error_m: f64,
    /// Frames where the outlines overlap but `δ < 0`.
    pub missed_contact_frames: usize,
    /// Foundation: the deepest overlap over the nominal clearance.
    pub max_overlap_ratio: f64,
    /// Foundation: fewest nodes across a contact zone at frames overlapping by more than 1 %
    /// of the clearance (`None`: no such frame).
    pub narrowest_zone_cells: Option<u32>,
    /// Foundation: most separate contact zones seen at one frame.
    pub max_contact_zones: u32,
    /// Foundation: the largest estimated load error from the zones' resolution (see
    /// `contact::ContactDiagnostics::resolution_error`), at frames overlapping by more than 1 %
    /// of the clearance.
    pub max_resolution_error: f64,
    /// Thin gap: the largest share of the overlap its neglected terms reached (see
    /// `contact::ContactDiagnostics::neglected_terms`), at frames overlapping by more than 1 %
    /// of the clearance.
    pub max_neglected_terms: f64,
    /// Median elastic share of the per-cycle force peaks after the start-up window (`None`:
    /// not judged, e.g. no peak after the window).
    pub elastic_share_median: Option<f64>,
    /// The limits applied.
    pub limits: ValidityLimits,
}

/// Accumulates the measures frame by frame.
#[derive(Debug, Clone)]
pub struct ValidityTally {
    clearance: f64,
    validity: Validity,
}

impl ValidityTally {
    /// An empty tally for a joint of nominal clearance `clearance` (m) on contact model
    /// `model`, judged by the measures the model names.
    pub fn new(clearance: f64, limits: ValidityLimits, model: &impl ContactModel) -> Self {
        Self {
            clearance,
            validity: Validity {
                model: model.name(),
                measures: model.validity_measures(),
                inside: true,
                reasons: Vec::new(),
                loaded_frames: 0,
                max_slope_ratio: 0.0,
                max_conformity_ratio: 0.0,
                penetrating_frames: 0,
                unloaded_penetrating_frames: 0,
                overlap_frames: 0,
                max_overlap_error_m: 0.0,
                missed_contact_frames: 0,
                max_overlap_ratio: 0.0,
                narrowest_zone_cells: None,
                max_contact_zones: 0,
                max_resolution_error: 0.0,
                max_neglected_terms: 0.0,
                elastic_share_median: None,
                limits,
            },
        }
    }

    /// Adds one output frame; `overlap` is the true outline overlap where it was measured.
    pub fn frame(&mut self, d: &ContactDiagnostics, overlap: Option<f64>) {
        let judged = |m: ValidityMeasure| self.validity.measures.contains(&m);
        let (overlap_ratio, resolution, slope, conformity) = (
            judged(ValidityMeasure::OverlapRatio),
            judged(ValidityMeasure::ResolutionError),
            judged(ValidityMeasure::SlopeRatio),
            judged(ValidityMeasure::Conformity),
        );
        let neglected = judged(ValidityMeasure::NeglectedTerms);
        let v = &mut self.validity;
        if neglected && d.penetration > 0.01 * self.clearance {
            v.max_neglected_terms = v.max_neglected_terms.max(d.neglected_terms);
        }
        if overlap_ratio {
            v.max_overlap_ratio = v.max_overlap_ratio.max(d.penetration / self.clearance);
        }
        if resolution {
            v.max_contact_zones = v.max_contact_zones.max(d.contact_zones);
            if d.penetration > 0.01 * self.clearance && d.contact_zones > 0 {
                v.max_resolution_error = v.max_resolution_error.max(d.resolution_error);
                v.narrowest_zone_cells = Some(
                    v.narrowest_zone_cells
                        .map_or(d.narrowest_zone_cells, |n| n.min(d.narrowest_zone_cells)),
                );
            }
        }
        if d.in_contact && d.normal_force > 0.0 {
            v.loaded_frames += 1;
            if slope {
                let ratio = (d.bearing_slope - d.pin_slope).abs() / d.eccentricity;
                v.max_slope_ratio = v.max_slope_ratio.max(ratio);
            }
            if conformity {
                let local_clearance = d.bearing_radius - d.pin_radius;
                let ratio = (d.pin_curvature - d.bearing_curvature) / local_clearance;
                v.max_conformity_ratio = v.max_conformity_ratio.max(ratio);
            }
        }
        if d.penetration > 0.01 * self.clearance {
            v.penetrating_frames += 1;
            if d.normal_force == 0.0 {
                v.unloaded_penetrating_frames += 1;
            }
        }
        if let Some(overlap) = overlap {
            v.overlap_frames += 1;
            // Contact depths only: two negative gaps of different size are both "free".
            v.max_overlap_error_m = v
                .max_overlap_error_m
                .max((overlap.max(0.0) - d.penetration.max(0.0)).abs());
            if overlap > 0.0 && d.penetration < 0.0 {
                v.missed_contact_frames += 1;
            }
        }
    }

    /// The verdict.
    pub fn finish(mut self) -> Validity {
        let v = &mut self.validity;
        let l = v.limits;
        let fraction = |part: usize, whole: usize| {
            if whole == 0 {
                0.0
            } else {
                part as f64 / whole as f64
            }
        };
        let clearance = self.clearance;
        let verdict = |measure: &ValidityMeasure| -> (bool, String) {
            match measure {
                ValidityMeasure::OverlapRatio => (
                    v.max_overlap_ratio > l.overlap_ratio,
                    format!(
                        "the outlines overlap by up to {:.2} of the clearance, more than a thin \
                             layer describes (limit {})",
                        v.max_overlap_ratio, l.overlap_ratio
                    ),
                ),
                ValidityMeasure::ResolutionError => (
                    v.max_resolution_error > l.resolution_error,
                    format!(
                        "contact zones as narrow as {} nodes carry the load: the nodes resolve it \
                             to about {:.1} % (limit {:.0} %; a finer contact.cells, a multiple of \
                             wear.cells, resolves it better)",
                        v.narrowest_zone_cells.unwrap_or(0),
                        100.0 * v.max_resolution_error,
                        100.0 * l.resolution_error
                    ),
                ),
                ValidityMeasure::NeglectedTerms => (
                    v.max_neglected_terms > l.neglected_terms,
                    format!(
                        "the thin-gap overlap neglects terms up to {:.2} % of the overlap (limit \
                             {:.0} %): the eccentricity or the outlines' slopes are too large for \
                             it; the foundation describes them",
                        100.0 * v.max_neglected_terms,
                        100.0 * l.neglected_terms
                    ),
                ),
                ValidityMeasure::SlopeRatio => (
                    v.max_slope_ratio > l.slope_ratio,
                    format!(
                        "profile slope |R_i' − R_j'|/|e| reaches {:.2} (limit {})",
                        v.max_slope_ratio, l.slope_ratio
                    ),
                ),
                ValidityMeasure::Conformity => (
                    v.max_conformity_ratio > l.conformity_ratio,
                    format!(
                        "the worn dent is {:.1}× as curved as the pin can follow, (R_j'' − R_i'')/c \
                             (limit {})",
                        v.max_conformity_ratio, l.conformity_ratio
                    ),
                ),
                ValidityMeasure::UnloadedPenetration => (
                    fraction(v.unloaded_penetrating_frames, v.penetrating_frames)
                        > l.unloaded_fraction,
                    format!(
                        "{} of {} frames with δ > 1 % of the clearance carry no force",
                        v.unloaded_penetrating_frames, v.penetrating_frames
                    ),
                ),
                ValidityMeasure::OverlapError => (
                    v.max_overlap_error_m > l.overlap_error * clearance,
                    format!(
                        "the true overlap of the worn outlines differs from δ by up to {:.1} µm \
                             ({:.0} % of the clearance; limit {:.0} %)",
                        v.max_overlap_error_m * 1e6,
                        100.0 * v.max_overlap_error_m / clearance,
                        100.0 * l.overlap_error
                    ),
                ),
                ValidityMeasure::MissedContacts => (
                    fraction(v.missed_contact_frames, v.overlap_frames) > l.missed_contact_fraction,
                    format!(
                        "in {} of {} checked frames the outlines overlap where δ < 0 (missed \
                             contacts)",
                        v.missed_contact_frames, v.overlap_frames
                    ),
                ),
            }
        };
        let checks: Vec<(bool, String)> = v.measures.iter().map(verdict).collect();
        v.reasons = checks
            .into_iter()
            .filter(|(failed, _)| *failed)
            .map(|(_, reason)| reason)
            .collect();
        v.inside = v.reasons.is_empty();
        self.validity
    }
}

impl Validity {
    /// The model's measures in one line for reports, e.g. `line of centres: slope |c'|/|e| ≤
    /// 0.12, conformity ≤ 0.40` (the measures with a value to show; every failed one is in
    /// [`Validity::reasons`]).
    pub fn measured(&self) -> String {
        let shown: Vec<String> = self
            .measures
            .iter()
            .filter_map(|measure| match measure {
                ValidityMeasure::OverlapRatio => {
                    Some(format!("overlap ≤ {:.3} c0", self.max_overlap_ratio))
                }
                ValidityMeasure::ResolutionError => Some(format!(
                    "load error from the grid ≤ {:.2} %, narrowest loaded zone {} nodes",
                    100.0 * self.max_resolution_error,
                    self.narrowest_zone_cells.unwrap_or(0)
                )),
                ValidityMeasure::NeglectedTerms => Some(format!(
                    "neglected terms ≤ {:.3} % of the overlap",
                    100.0 * self.max_neglected_terms
                )),
                ValidityMeasure::SlopeRatio => {
                    Some(format!("slope |c'|/|e| ≤ {:.2}", self.max_slope_ratio))
                }
                ValidityMeasure::Conformity => {
                    Some(format!("conformity ≤ {:.2}", self.max_conformity_ratio))
                }
                ValidityMeasure::UnloadedPenetration
                | ValidityMeasure::OverlapError
                | ValidityMeasure::MissedContacts => None,
            })
            .collect();
        format!("{}: {}", self.model.replace('-', " "), shown.join(", "))
    }

    /// Judges the response's force peaks by their median elastic share (any contact model): a
    /// response whose peaks are mostly the damping term of its law has no force results.
    pub fn judge_elastic_share(&mut self, share: f64) {
        if !share.is_finite() {
            return;
        }
        self.elastic_share_median = Some(share);
        if share < self.limits.elastic_share {
            self.reasons.push(format!(
                "the median force peak is only {:.0} % elastic: the rest is the damping term of \
                 the law, not a load the surfaces carry (limit {:.0} %)",
                100.0 * share,
                100.0 * self.limits.elastic_share
            ));
            self.inside = false;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use contact::{Foundation, LineOfCentres};

    fn foundation() -> Foundation {
        Foundation::with_layer(1e14, 0.01).expect("a positive layer")
    }

    fn loaded(slope: f64, curvature: f64) -> ContactDiagnostics {
        ContactDiagnostics {
            in_contact: true,
            penetration: 2e-5,
            eccentricity: 5.2e-4,
            bearing_radius: 0.05,
            pin_radius: 0.0495,
            normal_force: 1e4,
            bearing_slope: slope,
            pin_curvature: curvature,
            ..ContactDiagnostics::default()
        }
    }

    #[test]
    fn round_contacts_are_inside_and_each_measure_can_fail() {
        let clearance = 5e-4;
        let mut round = ValidityTally::new(clearance, ValidityLimits::default(), &LineOfCentres);
        for _ in 0..100 {
            round.frame(&loaded(0.0, 0.0), Some(2e-5));
        }
        let v = round.finish();
        assert!(v.inside, "{v:?}");
        assert_eq!((v.loaded_frames, v.penetrating_frames), (100, 100));

        // Slope 0.4 × |e| and conformity 1.2: both beyond their limits.
        let mut steep = ValidityTally::new(clearance, ValidityLimits::default(), &LineOfCentres);
        steep.frame(&loaded(0.4 * 5.2e-4, 1.2 * 5e-4), None);
        let v = steep.finish();
        assert!(!v.inside);
        assert_eq!(v.reasons.len(), 2, "{:?}", v.reasons);
        assert!((v.max_slope_ratio - 0.4).abs() < 1e-12);
        assert!((v.max_conformity_ratio - 1.2).abs() < 1e-12);

        // A contact the line of centres misses, and a penetrating frame without force.
        let mut missed = ValidityTally::new(clearance, ValidityLimits::default(), &LineOfCentres);
        let free = ContactDiagnostics {
            penetration: -1e-5,
            ..ContactDiagnostics::default()
        };
        missed.frame(&free, Some(8e-5));
        let unloaded = ContactDiagnostics {
            normal_force: 0.0,
            ..loaded(0.0, 0.0)
        };
        missed.frame(&unloaded, None);
        let v = missed.finish();
        assert_eq!(v.missed_contact_frames, 1);
        assert_eq!(v.unloaded_penetrating_frames, 1);
        assert!((v.max_overlap_error_m - 8e-5).abs() < 1e-18);
        assert_eq!(v.reasons.len(), 3, "{:?}", v.reasons);
        // Two gaps of different size are no error.
        let mut apart = ValidityTally::new(clearance, ValidityLimits::default(), &LineOfCentres);
        apart.frame(&free, Some(-2e-4));
        assert!(apart.finish().inside);
    }

    #[test]
    fn foundation_measures_overlap_and_loaded_zones_and_each_can_fail() {
        let clearance = 5e-4;
        let frame = |penetration: f64, zones: u32, narrowest: u32| ContactDiagnostics {
            in_contact: penetration > 0.0,
            penetration,
            normal_force: if penetration > 0.0 { 1e4 } else { 0.0 },
            contact_zones: zones,
            narrowest_zone_cells: narrowest,
            // One zone of that width carrying the whole load.
            resolution_error: 0.96 / f64::from(narrowest).powi(2),
            ..ContactDiagnostics::default()
        };
        let mut fine = ValidityTally::new(clearance, ValidityLimits::default(), &foundation());
        fine.frame(&frame(2e-5, 1, 40), None);
        // A light touch of one node (overlap below 1 % of c) does not count as a zone.
        fine.frame(&frame(1e-6, 1, 1), None);
        let v = fine.finish();
        assert!(v.inside, "{v:?}");
        assert_eq!(v.model, "foundation");
        assert_eq!(v.narrowest_zone_cells, Some(40));
        assert!((v.max_overlap_ratio - 0.04).abs() < 1e-12);

        let mut coarse = ValidityTally::new(clearance, ValidityLimits::default(), &foundation());
        coarse.frame(&frame(2e-5, 2, 3), None);
        coarse.frame(&frame(1.5e-4, 1, 60), None);
        let v = coarse.finish();
        assert_eq!(v.reasons.len(), 2, "{:?}", v.reasons);
        assert_eq!(v.narrowest_zone_cells, Some(3));
        assert_eq!(v.max_contact_zones, 2);
        // Slopes and missed contacts are the line of centres' measures: not applied here.
        let mut unloaded = ValidityTally::new(clearance, ValidityLimits::default(), &foundation());
        unloaded.frame(
            &ContactDiagnostics {
                normal_force: 0.0,
                ..frame(2e-5, 1, 40)
            },
            Some(8e-5),
        );
        let v = unloaded.finish();
        assert!(v.inside, "{v:?}");
        assert_eq!(v.unloaded_penetrating_frames, 1);
    }

    /// A response whose median force peak is mostly damping leaves validity with a reason; one
    /// that is mostly elastic, or whose share is unknown, keeps its verdict.
    #[test]
    fn a_mostly_damped_force_peak_is_outside_validity() {
        for (share, inside) in [(0.3, false), (0.49, false), (0.5, true), (0.97, true)] {
            let mut v = ValidityTally::new(5e-4, ValidityLimits::default(), &foundation()).finish();
            assert!(v.inside);
            v.judge_elastic_share(share);
            assert_eq!(v.inside, inside, "share {share}");
            assert_eq!(v.elastic_share_median, Some(share));
            assert_eq!(
                v.reasons.iter().any(|r| r.contains("% elastic")),
                !inside,
                "{:?}",
                v.reasons
            );
        }
        let mut v = ValidityTally::new(5e-4, ValidityLimits::default(), &foundation()).finish();
        v.judge_elastic_share(f64::NAN);
        assert!(v.inside && v.elastic_share_median.is_none());
    }
}
