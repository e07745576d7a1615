//! What a caller keeps for a joint's evaluations ([`ContactWorkspace`]): its model's workspace,
//! and which joint's tables it was filled against.

use std::sync::atomic::{AtomicU64, Ordering};

use super::kind::ModelWorkspace;

/// Names one build of a joint's model tables: a joint and its clones share it, a joint built
/// anew (another model, new profiles) gets another.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct TablesKey(u64);

impl TablesKey {
    pub(super) fn new() -> Self {
        static NEXT: AtomicU64 = AtomicU64::new(0);
        Self(NEXT.fetch_add(1, Ordering::Relaxed))
    }
}

/// What a joint's evaluations carry from one to the next: the model's workspace
/// ([`crate::ContactModel::Workspace`]), owned by the caller and passed to each evaluation
/// (`ClearanceJoint::forces_in` and the other `_in` evaluations). Made by
/// [`super::ClearanceJoint::workspace`] for one joint (and its clones); handed to a joint with
/// other tables it is made anew for that joint. The default is empty: evaluations with it give
/// the same results and keep nothing.
#[derive(Clone, Debug, Default)]
pub struct ContactWorkspace {
    /// The tables it was made for (`None`: empty, for any).
    tables: Option<TablesKey>,
    model: ModelWorkspace,
}

impl ContactWorkspace {
    pub(super) fn new(tables: TablesKey, model: ModelWorkspace) -> Self {
        Self {
            tables: Some(tables),
            model,
        }
    }

    /// The model's workspace for the tables `key`: this one's if it was made for them or is
    /// empty, else a new one from `make`.
    pub(super) fn for_tables(
        &mut self,
        key: TablesKey,
        make: impl FnOnce() -> ModelWorkspace,
    ) -> &mut ModelWorkspace {
        if self.tables.is_some_and(|tables| tables != key) {
            *self = Self::new(key, make());
        }
        &mut self.model
    }
}
