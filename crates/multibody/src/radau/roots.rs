//! Root location over an accepted step, on the dense output: the event functions' sign
//! changes, found by the Illinois-modified secant method of SUNDIALS (as diffsol does).

use super::{Radau5, RadauStop};

impl Radau5<'_> {
    /// Sign changes of the root functions over the last step, located on the dense output
    /// by the Illinois-modified secant method of SUNDIALS (as diffsol does).
    pub(super) fn check_roots(&mut self) -> Option<RadauStop> {
        let (g, _) = self.roots?;
        let mut g1 = std::mem::take(&mut self.scratch.g1);
        let mut gmid = std::mem::take(&mut self.scratch.gmid);
        let mut ymid = std::mem::take(&mut self.scratch.ymid);
        g(self.y.as_slice(), &[], self.t, &mut g1);
        let result = match sign_change(&self.g0, &g1) {
            (zero, None) => {
                std::mem::swap(&mut self.g0, &mut g1);
                zero.then(|| RadauStop::Root(self.t, closest_to_zero(&self.g0)))
            }
            (_, Some(mut index)) => {
                let (mut t0, mut t1) = (self.t_old, self.t);
                let tol = 100.0 * f64::EPSILON * (t1.abs() + (t1 - t0).abs());
                let mut alpha = 1.0;
                let mut side = [false, true];
                let mut i = 0;
                let mut found = None;
                while (t1 - t0).abs() > tol {
                    let (a, b) = (g1[index], self.g0[index]);
                    let mut mid = t1 - (t1 - t0) * a / (a - alpha * b);
                    let fraction = |span: f64| {
                        let fracint = span / tol;
                        if fracint > 5.0 { 0.1 } else { 0.5 / fracint }
                    };
                    if (mid - t0).abs() < 0.5 * tol {
                        mid = t0 + fraction((t1 - t0).abs()) * (t1 - t0);
                    }
                    if (t1 - mid).abs() < 0.5 * tol {
                        mid = t1 - fraction((t1 - t0).abs()) * (t1 - t0);
                    }
                    if self.interpolate(mid, &mut ymid).is_err() {
                        break;
                    }
                    g(&ymid, &[], mid, &mut gmid);
                    let (zero, lower) = sign_change(&self.g0, &gmid);
                    if let Some(k) = lower {
                        t1 = mid;
                        index = k;
                        std::mem::swap(&mut g1, &mut gmid);
                    } else if zero {
                        found = Some(mid);
                        break;
                    } else {
                        t0 = mid;
                        std::mem::swap(&mut self.g0, &mut gmid);
                    }
                    side[i % 2] = lower.is_some();
                    if i >= 2 {
                        alpha = if side[0] != side[1] {
                            1.0
                        } else if side[0] {
                            0.5 * alpha
                        } else {
                            2.0 * alpha
                        };
                    }
                    i += 1;
                }
                g(self.y.as_slice(), &[], self.t, &mut self.g0);
                Some(RadauStop::Root(found.unwrap_or(t1), index))
            }
        };
        self.scratch.g1 = g1;
        self.scratch.gmid = gmid;
        self.scratch.ymid = ymid;
        result
    }
}

/// Whether some `g1` is exactly zero, and the function with a sign change whose crossing is
/// closest to the step's end (SUNDIALS' rule).
fn sign_change(g0: &[f64], g1: &[f64]) -> (bool, Option<usize>) {
    let mut zero = false;
    let mut best = (0.0, None);
    for (i, (&a, &b)) in g0.iter().zip(g1).enumerate() {
        if b == 0.0 {
            zero = true;
        }
        if a * b < 0.0 {
            let q = (b / (b - a)).abs();
            if q > best.0 {
                best = (q, Some(i));
            }
        }
    }
    (zero, best.1)
}

fn closest_to_zero(g: &[f64]) -> usize {
    g.iter()
        .enumerate()
        .min_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
        .map_or(0, |(i, _)| i)
}
