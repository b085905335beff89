//! The timed analysis of each assertion, for the tests of constructs of
//! tock-CSP: a plain assertion is also checked untimed (RT-8), which
//! `untimed.rs` tests.

#![allow(dead_code)] // Each test binary uses a different part.

use robosim_engine::verify::{Options, Report, Semantics};

/// [`robosim_engine::verify::verify_texts`], timed reports only.
pub fn verify_texts(files: impl IntoIterator<Item = (String, String)>, opts: &Options) -> Vec<Report> {
    timed(robosim_engine::verify::verify_texts(files, opts))
}

fn timed(reports: Vec<Report>) -> Vec<Report> {
    reports.into_iter().filter(|r| r.semantics == Semantics::Timed).collect()
}
