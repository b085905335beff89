//! The database.

/// The query interface every part of the semantic model is written against.
#[salsa::db]
pub trait Db: salsa::Database {}

/// The concrete database. Cheap to clone: clones share storage, and a clone
/// can be sent to another thread for read-only work.
#[salsa::db]
#[derive(Default, Clone)]
pub struct RootDatabase {
    storage: salsa::Storage<Self>,
}

#[salsa::db]
impl salsa::Database for RootDatabase {}

#[salsa::db]
impl Db for RootDatabase {}

impl RootDatabase {
    /// A database that reports every salsa event to `on_event` (tests use
    /// it to check which queries re-execute after an edit).
    pub fn with_event_log(on_event: impl Fn(salsa::Event) + Send + Sync + 'static) -> RootDatabase {
        RootDatabase { storage: salsa::Storage::new(Some(Box::new(on_event))) }
    }
}
