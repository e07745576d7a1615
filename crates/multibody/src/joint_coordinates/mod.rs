//! Joint-coordinate formulation: the equations of motion in the relative coordinates of a
//! spanning tree of the ideal joints ([`crate::Formulation::JointCoordinates`]).
//!
//! Where ideal joints form a tree (the LGRES, whose two loops are cut by its clearance joints),
//! the tree's coordinates satisfy every joint by construction: no multipliers, no Baumgarte
//! terms, no drift, and a state of `2 × (free coordinates)` instead of `2 × 3 × bodies`.
//! Joints that close a loop, and drivers that do not prescribe a tree coordinate, stay
//! constraints with multipliers and Baumgarte stabilisation (the mixed formulation), so every
//! model the Cartesian formulation accepts runs here too. Force elements see Cartesian `q, q̇`
//! as before; their exact partials are chained through the tree's Jacobian
//! ([`evaluator`]'s docs give the equations). The tree and its kinematics: [`tree`].

pub(crate) mod evaluator;
pub(crate) mod scalar;
pub(crate) mod tree;

pub(crate) use evaluator::JointEvaluator;
pub(crate) use tree::Tree;

#[cfg(test)]
mod tests;
