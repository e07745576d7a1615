//! Where a sweep's rows keep what its combined life ([`crate::life`]) reads: when the base scene
//! sets `run.clearance_limit`, each wearing joint's cycles to it and their noise, as metrics the
//! sweep adds to the file's.

use scene::Scene;

/// The metric a sweep keeps of joint `joint`'s cycles to the limit, and of their noise.
pub fn joint_metrics(joint: &str) -> [String; 2] {
    [
        format!("wear.joints.{joint}.clearance_limit.cycles"),
        format!("wear.joints.{joint}.clearance_limit.cycles_noise"),
    ]
}

/// What a sweep whose base `scene` sets `run.clearance_limit` keeps besides the file's
/// metrics: each wearing joint's [`joint_metrics`] (none without a limit).
pub fn life_metrics(scene: &Scene) -> Vec<String> {
    if scene.run.clearance_limit.is_none() {
        return Vec::new();
    }
    scene
        .active_clearance_joints()
        .filter(|c| c.wear.is_some())
        .flat_map(|c| joint_metrics(&c.name))
        .collect()
}

/// What a sweep's combined life reads from its rows ([`crate::life::combine`]).
#[derive(Debug, Clone, PartialEq)]
pub struct LifeColumns {
    /// The base scene's `run.clearance_limit`, m.
    pub limit_m: f64,
    /// Its `run.k_d_correlation`.
    pub correlation: scene::KdCorrelation,
    /// Per wearing joint: its name, and the indices among the metrics of its cycles to the
    /// limit and of their noise.
    pub joints: Vec<(String, usize, usize)>,
}

impl LifeColumns {
    /// With a clearance limit in `scene`: its wearing joints' [`life_metrics`] appended to
    /// `metrics` (those not there already) and where each is; `None` without a limit.
    pub fn of(scene: &Scene, metrics: &mut Vec<String>) -> Option<LifeColumns> {
        let limit_m = scene.run.clearance_limit?;
        for m in life_metrics(scene) {
            if !metrics.contains(&m) {
                metrics.push(m);
            }
        }
        let joints = scene
            .active_clearance_joints()
            .filter(|c| c.wear.is_some())
            .filter_map(|c| {
                let [cycles, noise] = joint_metrics(&c.name);
                let at = |m: &String| metrics.iter().position(|x| x == m);
                Some((c.name.clone(), at(&cycles)?, at(&noise)?))
            })
            .collect();
        Some(LifeColumns {
            limit_m,
            correlation: scene.run.k_d_correlation,
            joints,
        })
    }
}
