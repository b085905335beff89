//! The timed analysis of each assertion, for the tests of constructs of
//! tock-CSP: a plain assertion is also checked untimed (RT-8), which
//! `untimed.rs` tests.

#![allow(dead_code)] // Each test binary uses a different part.

use robosim_engine::budget::ProgressFn;
use robosim_engine::verify::{Options, Report, Semantics};
use robosim_hir::{Db, Workspace};

/// [`robosim_engine::verify::verify_texts`], timed reports only.
pub fn verify_texts(files: impl IntoIterator<Item = (String, String)>, opts: &Options) -> Vec<Report> {
    timed(robosim_engine::verify::verify_texts(files, opts))
}

/// [`robosim_engine::verify::verify_workspace`], timed reports only.
pub fn verify_workspace(db: &dyn Db, ws: Workspace, opts: &Options, progress: Option<ProgressFn>) -> Vec<Report> {
    timed(robosim_engine::verify::verify_workspace(db, ws, opts, progress))
}

fn timed(reports: Vec<Report>) -> Vec<Report> {
    reports.into_iter().filter(|r| r.semantics == Semantics::Timed).collect()
}
