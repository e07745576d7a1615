//! The streaming sum over the nodes: each segment's exact energy, the nodes waiting for the
//! segments to their right, and the forces they add to both bodies.

use super::geometry::{Node, cross};
use crate::diagnostics::ContactDiagnostics;
use crate::joint::dual::Real;

/// `∫₀¹ max(0, a + (b − a)s)² ds` and its partials in `a` and `b` (the exact energy of one
/// segment between two nodes, see the module docs).
#[inline]
pub(in crate::joint) fn segment<T: Real>(a: T, b: T) -> (T, T, T) {
    let (av, bv) = (a.value(), b.value());
    let zero = T::constant(0.0);
    if av >= 0.0 && bv >= 0.0 {
        let q = (a * a + a * b + b * b) / 3.0;
        (q, (a * 2.0 + b) / 3.0, (a + b * 2.0) / 3.0)
    } else if av > 0.0 {
        let span = a - b;
        let a2 = a * a;
        let q = a2 * a / (span * 3.0);
        let dq_db = q / span;
        (q, a2 * (a * 2.0 - b * 3.0) / (span * span * 3.0), dq_db)
    } else if bv > 0.0 {
        let span = b - a;
        let b2 = b * b;
        let q = b2 * b / (span * 3.0);
        let dq_da = q / span;
        (q, dq_da, b2 * (b * 2.0 - a * 3.0) / (span * span * 3.0))
    } else {
        (zero, zero, zero)
    }
}

/// What one evaluation gives: generalized forces `(F_x, F_y, M)` on bearing and pin bodies.
pub(in crate::joint) struct Output<T> {
    pub(in crate::joint) bearing: [T; 3],
    pub(in crate::joint) pin: [T; 3],
    pub(in crate::joint) diagnostics: ContactDiagnostics,
}

/// Adds a node's force on the pin (at its point) to both bodies' generalized forces.
#[inline]
pub(super) fn apply<T: Real>(out: &mut Output<T>, node: &Node<T>, force_on_pin: [T; 2]) {
    out.pin[0] = out.pin[0] + force_on_pin[0];
    out.pin[1] = out.pin[1] + force_on_pin[1];
    out.pin[2] = out.pin[2] + cross(&node.pin_arm, &force_on_pin);
    out.bearing[0] = out.bearing[0] - force_on_pin[0];
    out.bearing[1] = out.bearing[1] - force_on_pin[1];
    out.bearing[2] = out.bearing[2] - cross(&node.bearing_arm, &force_on_pin);
}

/// A computed node waiting for the segments to its right, with the partials of the energy in
/// its overlap gathered so far: from the segments to its neighbours (`fine`) and, for
/// Simpson's even nodes, to the even nodes two apart (`coarse`, in units of the node weight).
#[derive(Clone, Copy)]
pub(super) struct Pending<T> {
    pub(super) index: i64,
    pub(super) node: Node<T>,
    pub(super) fine: T,
    pub(super) coarse: T,
}

/// The nodes waiting to be closed, oldest first: at most three (`k − 2`, `k − 1`, `k`), in a
/// ring so that closing the oldest moves no node.
pub(super) struct NodeQueue<T> {
    pub(super) items: [Option<Pending<T>>; 3],
    /// The oldest node's slot.
    pub(super) head: usize,
    pub(super) len: usize,
}

impl<T: Copy> Default for NodeQueue<T> {
    fn default() -> Self {
        Self {
            items: [None; 3],
            head: 0,
            len: 0,
        }
    }
}

impl<T: Copy> NodeQueue<T> {
    pub(super) fn slot(&self, position: usize) -> usize {
        (self.head + position) % self.items.len()
    }

    pub(super) fn at(&mut self, index: i64) -> Option<&mut Pending<T>> {
        let slots = (0..self.len).map(|position| self.slot(position));
        let slot = slots
            .into_iter()
            .find(|&slot| self.items[slot].as_ref().is_some_and(|p| p.index == index))?;
        self.items[slot].as_mut()
    }

    pub(super) fn push(&mut self, pending: Pending<T>) {
        // Three at most (the module's stream closes a node once it is two behind): a fourth
        // would take the oldest's slot.
        debug_assert!(
            self.len < self.items.len(),
            "the node queue holds three nodes"
        );
        let slot = self.slot(self.len);
        self.items[slot] = Some(pending);
        self.len += 1;
    }

    pub(super) fn front(&self) -> Option<&Pending<T>> {
        if self.len == 0 {
            return None;
        }
        self.items[self.head].as_ref()
    }

    /// The oldest node.
    pub(super) fn pop(&mut self) -> Option<Pending<T>> {
        if self.len == 0 {
            return None;
        }
        let first = self.items[self.head].take()?;
        self.head = self.slot(1);
        self.len -= 1;
        Some(first)
    }
}

#[cfg(test)]
mod tests {
    use super::segment;

    /// The segment energy and its partials are continuous, with continuous partials, as a node
    /// crosses zero: the force is C¹ across a zone edge.
    #[test]
    fn segment_is_smooth_across_a_zone_edge() {
        let a = 3e-6;
        for b in [1e-14, -1e-14] {
            let (q, qa, qb) = segment(a, b);
            // Both sides of b = 0 give the edge values to within b/a = 3e-9.
            assert!((q / (a * a / 3.0) - 1.0).abs() < 1e-8, "{q}");
            assert!((qa / (2.0 * a / 3.0) - 1.0).abs() < 1e-8, "{qa}");
            assert!((qb / (a / 3.0) - 1.0).abs() < 1e-8, "{qb}");
        }
        // Second derivatives: ∂²Q/∂b² tends to 2/3 from both sides (2/3 · (a/(a − b))³ below).
        let h = 1e-11;
        let second = |b: f64| (segment(a, b + h).2 - segment(a, b - h).2) / (2.0 * h);
        for b in [1e-10, -1e-10] {
            assert!((second(b) - 2.0 / 3.0).abs() < 1e-3, "{}", second(b));
        }
        // Against a fine quadrature of the definition.
        for (a, b) in [(2e-6, -5e-6), (-1e-6, 4e-6), (1e-6, 2e-6), (-1.0, -2.0)] {
            let n = 200_000;
            let quad: f64 = (0..n)
                .map(|k| {
                    let s = (k as f64 + 0.5) / n as f64;
                    let v = f64::max(0.0, a + (b - a) * s);
                    v * v
                })
                .sum::<f64>()
                / n as f64;
            let (q, _, _) = segment(a, b);
            assert!(
                (q - quad).abs() <= 1e-8 * quad.max(1e-30),
                "{a} {b}: {q} vs {quad}"
            );
        }
    }
}
