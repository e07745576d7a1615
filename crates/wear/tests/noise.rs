//! The jackknife noise of staged wear against a closed form: runs whose two halves are
//! independent samples of a known variance.

mod common;

use common::joint;
use wear::{NOISE_GROUPS, NoiseBatches, StageWear, WornJoint, discrete_noise, jackknife_error};

/// A small deterministic generator (xorshift64*), uniform in [−√3, √3): unit variance.
struct Uniform(u64);

impl Uniform {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let u = (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64;
        3f64.sqrt() * (2.0 * u - 1.0)
    }
}

const CELLS: usize = 8;
/// Mean depth of a half per cell (cell 2 the deepest), m, and its standard deviation.
const MEAN: [f64; CELLS] = [1e-6, 1e-6, 3e-6, 1e-6, 1e-6, 1e-6, 1e-6, 1e-6];
const SPREAD: f64 = 0.2e-6;
const RUNS: usize = 37;
const REPEATS: usize = 400;

fn weight(run: usize) -> f64 {
    1.0 + (run % 3) as f64
}

/// One stage of `RUNS` runs: the batches and the stage's total wear (bearing, pin).
fn stage(joint: &WornJoint, random: &mut Uniform) -> (NoiseBatches, Vec<f64>, Vec<f64>) {
    let mut batches = NoiseBatches::new(std::slice::from_ref(joint), NOISE_GROUPS);
    let (mut bearing, mut pin) = (vec![0.0; CELLS], vec![0.0; CELLS]);
    for run in 0..RUNS {
        let mut half = || {
            let depths: Vec<f64> = MEAN.iter().map(|m| m + SPREAD * random.next()).collect();
            StageWear::from_depths(joint, depths.clone(), depths).unwrap()
        };
        let halves = [half(), half()];
        for h in &halves {
            for (total, d) in bearing.iter_mut().zip(h.bearing()) {
                *total += weight(run) * d;
            }
            for (total, d) in pin.iter_mut().zip(h.pin()) {
                *total += weight(run) * d;
            }
        }
        batches.add(&[halves], weight(run));
        // A run the stage did not use counts for nothing.
        batches.add(&[[half(), half()]], 0.0);
    }
    (batches, bearing, pin)
}

/// The noise the jackknife reports is the closed form's: over many stages, its mean square
/// matches `Σ a_r² · 2σ²` for a linear measure (one cell) and for the peak of a profile whose
/// peak stands clear of its neighbours.
#[test]
fn jackknife_noise_matches_independent_samples() {
    let joint = joint(CELLS);
    let mut random = Uniform(0x9E37_79B9_7F4A_7C15);
    let exact: f64 = (0..RUNS).map(|r| 2.0 * (weight(r) * SPREAD).powi(2)).sum();
    let (mut cell, mut peak, mut scatter) = (0.0, 0.0, 0.0);
    let expected_peak: f64 = (0..RUNS).map(|r| 2.0 * weight(r) * MEAN[2]).sum();
    for _ in 0..REPEATS {
        let (batches, bearing, pin) = stage(&joint, &mut random);
        let replicas = &batches.replicas()[0];
        assert_eq!(replicas.count(), 2 * NOISE_GROUPS);
        cell += replicas.noise(&bearing, &pin, |b, _| b[5]).unwrap().powi(2);
        let top = |h: &[f64]| h.iter().copied().fold(0.0, f64::max);
        peak += replicas
            .noise(&bearing, &pin, |_, p| top(p))
            .unwrap()
            .powi(2);
        scatter += (top(&bearing) - expected_peak).powi(2);
    }
    let n = REPEATS as f64;
    let (cell, peak, scatter) = (cell / n, peak / n, scatter / n);
    println!(
        "exact noise {:.4e}; jackknife rms: cell {:.4e}, peak {:.4e}; the peaks' scatter {:.4e}",
        exact.sqrt(),
        cell.sqrt(),
        peak.sqrt(),
        scatter.sqrt()
    );
    for (what, variance) in [("cell", cell), ("peak", peak), ("scatter", scatter)] {
        assert!(
            (variance / exact - 1.0).abs() < 0.1,
            "{what}: variance {variance:e} against {exact:e}"
        );
    }
}

/// Over the plausible surfaces a measure linear in the depths deviates by exactly its
/// jackknife noise (root-mean-square, about their mean), times the scale asked for.
#[test]
fn plausible_surfaces_deviate_by_one_noise() {
    let joint = joint(CELLS);
    let mut random = Uniform(0x2545_F491_4F6C_DD1D);
    let (batches, bearing, pin) = stage(&joint, &mut random);
    let replicas = &batches.replicas()[0];
    let linear = |b: &[f64], p: &[f64]| 0.3 * b[1] + b[5] - 2.0 * p[2];
    let jackknife = replicas.noise(&bearing, &pin, linear).unwrap();
    for scale in [1.0, 0.4] {
        let values: Vec<f64> = replicas
            .plausible_surfaces(&bearing, &pin, scale)
            .iter()
            .map(|[b, p]| linear(b, p))
            .collect();
        let mean = values.iter().sum::<f64>() / values.len() as f64;
        let rms =
            (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / values.len() as f64).sqrt();
        println!("scale {scale}: rms {rms:.6e}, jackknife {jackknife:.6e}");
        assert!(
            (rms / (scale * jackknife) - 1.0).abs() < 1e-10,
            "scale {scale}: {rms:e} against {:e}",
            scale * jackknife
        );
    }
}

/// A count whose threshold sits at a cell's expected depth: it is 0 or 1 by chance over the
/// stages. The noise from the plausible surfaces has the mean square of the count's actual
/// scatter, where the jackknife's is off (a replica moves the depths by a nineteenth of their
/// noise; when it flips the count, the jackknife reads a whole unit); a threshold ten noises
/// away gives Laplace's floor and no scatter.
#[test]
fn a_counts_noise_matches_its_scatter() {
    let joint = joint(CELLS);
    let mut random = Uniform(0x0DDB_1A5E_5BAD_5EED);
    let expected: f64 = (0..RUNS).map(|r| 2.0 * weight(r) * MEAN[5]).sum();
    let exact: f64 = (0..RUNS).map(|r| 2.0 * (weight(r) * SPREAD).powi(2)).sum();
    let (mut counts, mut plausible, mut jackknife, mut far) = (Vec::new(), 0.0, 0.0, 0.0);
    for _ in 0..REPEATS {
        let (batches, bearing, pin) = stage(&joint, &mut random);
        let replicas = &batches.replicas()[0];
        let above =
            |threshold: f64| move |b: &[f64], _: &[f64]| f64::from(u8::from(b[5] >= threshold));
        let count = above(expected);
        let values = |measure: &dyn Fn(&[f64], &[f64]) -> f64| -> Vec<f64> {
            replicas
                .plausible_surfaces(&bearing, &pin, 1.0)
                .iter()
                .map(|[b, p]| measure(b, p))
                .collect()
        };
        counts.push(count(&bearing, &pin));
        plausible += discrete_noise(count(&bearing, &pin), &values(&count), 1.0)
            .unwrap()
            .powi(2);
        jackknife += jackknife_error(&replicas.values(&bearing, &pin, count))
            .unwrap()
            .powi(2);
        let distant = above(expected + 10.0 * exact.sqrt());
        far += discrete_noise(distant(&bearing, &pin), &values(&distant), 1.0)
            .unwrap()
            .powi(2);
    }
    let n = REPEATS as f64;
    let mean = counts.iter().sum::<f64>() / n;
    let scatter = counts.iter().map(|c| (c - mean).powi(2)).sum::<f64>() / n;
    let (plausible, jackknife, far) = (plausible / n, jackknife / n, far / n);
    println!(
        "count mean {mean:.3}: scatter variance {scatter:.4}, plausible {plausible:.4}, \
         jackknife {jackknife:.4}; ten noises away {far:.4}"
    );
    let floor = 1.0 / (2 * NOISE_GROUPS + 2) as f64;
    assert!(
        (plausible / scatter - 1.0).abs() < 0.25,
        "{plausible} against {scatter}"
    );
    assert!(
        (jackknife / scatter - 1.0).abs() > 0.5,
        "the jackknife {jackknife} reads the count's scatter: the plausible surfaces are moot"
    );
    assert!(
        (far / floor - 1.0).abs() < 1e-12,
        "{far} against Laplace's {floor}"
    );
}

/// Fewer than two batches holding samples measure nothing.
#[test]
fn one_batch_has_no_noise() {
    let joint = joint(CELLS);
    let mut batches = NoiseBatches::new(std::slice::from_ref(&joint), 1);
    let depths = MEAN.to_vec();
    let half = StageWear::from_depths(&joint, depths.clone(), depths.clone()).unwrap();
    assert!(
        batches.replicas()[0]
            .noise(&depths, &depths, |b, _| b[0])
            .is_none()
    );
    batches.add(&[[half.clone(), half]], 1.0);
    // One group, two halves: two replicas, identical halves, no noise.
    let replicas = &batches.replicas()[0];
    assert_eq!(replicas.count(), 2);
    assert_eq!(replicas.noise(&depths, &depths, |b, _| b[2]), Some(0.0));
}

/// A life curve of `steps` sub-steps: a trend of `rate` a sub-step plus fluctuations of unit
/// variance of which `survival` stays one sub-step later (`x_n = s x_{n−1} + ε_n`).
fn levelled_curve(random: &mut Uniform, steps: usize, survival: f64, rate: f64) -> Vec<f64> {
    let mut fluctuation = 0.0;
    (0..=steps)
        .map(|n| {
            if n > 0 {
                fluctuation = survival * fluctuation + random.next();
            }
            rate * n as f64 + fluctuation
        })
        .collect()
}

/// The levelled noise against the end's actual scatter: over many curves of a first-order
/// autoregression about a trend, the jackknife's noise (`√N` for unit fluctuations that all
/// stay) times the levelling share. Root mean square within 15 % of the ends' scatter with no
/// levelling (`s = 1`) and full levelling (`s = 0`); in between never below 0.85 of it (the
/// estimate leans to the jackknife where the survival is uncertain).
#[test]
fn levelled_noise_matches_the_scatter_of_the_end() {
    const STEPS: usize = 143;
    let mut random = Uniform(0x2545_F491_4F6C_DD1D);
    for survival in [0.0, 0.5, 0.9, 1.0] {
        let (mut printed, mut scatter) = (0.0, 0.0);
        for _ in 0..REPEATS {
            let curve = levelled_curve(&mut random, STEPS, survival, 3.0);
            printed += STEPS as f64 * wear::levelling(&curve, &[1.0; STEPS]).share.powi(2);
            scatter += (curve[STEPS] - 3.0 * STEPS as f64).powi(2);
        }
        let ratio = (printed / scatter).sqrt();
        println!("survival {survival}: levelled noise over the ends' scatter {ratio:.3}");
        if survival == 0.0 || survival == 1.0 {
            assert!((ratio - 1.0).abs() < 0.15, "survival {survival}: {ratio}");
        } else {
            assert!(ratio > 0.85, "survival {survival}: {ratio}");
        }
    }
}

/// Fluctuations that persist: increments `rate(n) + u_n` with `u_n = φ u_{n−1} + ε_n`
/// (stationary, a cubic trend of the rate over the stage). The jackknife, which counts the
/// sub-steps as independent, sees `N Var(u)`; times the persistence it should be the end's
/// scatter `Var(Σ u)`, `(1 + φ)/(1 − φ)` times more for large `N`. Root mean square within 15 %
/// of the scatter for φ = 0 (where the factor's floor of 1 may only lean up), 0.15 (about the
/// default LGRES's joint A) and 0.3 (measured 1.01, 0.92, 0.90; without the factor the last
/// two are 0.85 and 0.76 of it, and φ = 0.3 fails).
#[test]
fn persistent_fluctuations_are_counted() {
    const STEPS: usize = 141;
    let mut random = Uniform(0x9E37_79B9_7F4A_7C15);
    for phi in [0.0f64, 0.15, 0.3] {
        let (mut printed, mut jackknife, mut scatter) = (0.0, 0.0, 0.0);
        let marginal = 1.0 / (1.0 - phi * phi);
        for _ in 0..4 * REPEATS {
            let mut u = random.next() * marginal.sqrt();
            let mut sum = 0.0;
            let increments: Vec<f64> = (0..STEPS)
                .map(|n| {
                    if n > 0 {
                        u = phi * u + random.next();
                    }
                    sum += u;
                    let t = n as f64 / STEPS as f64;
                    5.0 - 3.0 * t + 2.0 * t * t * t + u
                })
                .collect();
            let independent = STEPS as f64 * marginal;
            printed += independent * wear::persistence(&increments).powi(2);
            jackknife += independent;
            scatter += sum * sum;
        }
        let (ratio, without) = ((printed / scatter).sqrt(), (jackknife / scatter).sqrt());
        println!(
            "φ {phi}: printed over the ends' scatter {ratio:.3} (without the persistence {without:.3})"
        );
        assert!((ratio - 1.0).abs() < 0.15, "φ {phi}: {ratio}");
    }
}

/// The persistence of a levelled curve (increments correlated negatively) or of one the cubic
/// takes out is 1, and the levelling's share carries it.
#[test]
fn persistence_is_one_without_positive_correlation() {
    let unit = [1.0; 39];
    let sawtooth: Vec<f64> = (0..40).map(|n| n as f64 + (n % 2) as f64).collect();
    let increments: Vec<f64> = sawtooth.windows(2).map(|w| w[1] - w[0]).collect();
    assert_eq!(wear::persistence(&increments), 1.0);
    let cubic: Vec<f64> = (0..60)
        .map(|n| (n as f64).powi(3) - 7.0 * n as f64)
        .collect();
    assert_eq!(wear::persistence(&cubic), 1.0);
    let levelling = wear::levelling(&sawtooth, &unit);
    assert_eq!(levelling.persistence, 1.0);
    // Runs of three alike (each run's value drawn): correlated by 2/3 and 1/3 at lags 1
    // and 2, so `1 + 2 (0.8 · 2/3 + 0.6 · 1/3)` at four lags, √2.47 = 1.57.
    let mut random = Uniform(0x0123_4567_89AB_CDEF);
    let draws: Vec<f64> = (0..40).map(|_| random.next()).collect();
    let blocks: Vec<f64> = (0..120).map(|n| draws[n / 3]).collect();
    let p = wear::persistence(&blocks);
    assert!((p - 1.57).abs() < 0.25, "{p}");
}

/// A curve too short, flat, or whose increments trend together keeps the jackknife's noise.
#[test]
fn short_flat_or_trending_curves_keep_the_jackknife() {
    let unit = [1.0; 39];
    let short: Vec<f64> = (0..wear::LEVELLING_MIN_STEPS).map(|n| n as f64).collect();
    assert_eq!(wear::levelling(&short, &unit[1..short.len()]).share, 1.0);
    assert_eq!(wear::levelling(&[2.0; 40], &unit).share, 1.0);
    // A growing rate: increments correlated positively.
    let trending: Vec<f64> = (0..40).map(|n| (n * n) as f64).collect();
    let levelling = wear::levelling(&trending, &unit);
    assert_eq!((levelling.survival, levelling.share), (1.0, 1.0));
    // A sawtooth (each step undone by the next) survives nothing.
    let sawtooth: Vec<f64> = (0..40).map(|n| n as f64 + (n % 2) as f64).collect();
    assert!(wear::levelling(&sawtooth, &unit).share < 0.2);
    // Sub-steps five times longer from the middle on: the rate does not trend.
    let lengths: Vec<f64> = (0..39).map(|n| if n < 20 { 1.0 } else { 5.0 }).collect();
    let mut value = 0.0;
    let stretched: Vec<f64> = std::iter::once(0.0)
        .chain(lengths.iter().enumerate().map(|(n, l)| {
            value += l * (1.0 + if n % 2 == 0 { 0.5 } else { -0.5 });
            value
        }))
        .collect();
    assert!(wear::levelling(&stretched, &lengths).share < 0.2);
    assert_eq!(wear::levelling(&stretched, &unit).share, 1.0);
    // Lengths that do not fit the curve: the jackknife's.
    assert_eq!(wear::levelling(&sawtooth, &unit[1..]).share, 1.0);
}
