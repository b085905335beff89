//! Computing and publishing diagnostics.
//!
//! Every change starts a job on a background thread (`background.rs`: a
//! lower priority than the threads answering requests). The job takes a
//! snapshot, computes, drops the snapshot, then publishes, in that order,
//! so no snapshot is ever held while waiting for a lock or for the client:
//! a write to the database (which waits for all snapshots) can always
//! proceed. Staleness is checked twice: a job whose file changed again
//! before it started does nothing (the newer job covers it), and a result
//! is published only if its file is still at the `seq` it was computed
//! from, checked under the publish lock so that versions never go backwards
//! on the wire. A newer edit cancels an older job's queries through salsa;
//! there is no debounce.
//!
//! An edited buffer gets one or two publishes for its new version. The
//! syntax-only one comes from a parse alone: the syntax diagnostics of the
//! new text, plus the semantic diagnostics of the last complete check moved
//! along with the edits made since (what editors do with markers anyway).
//! The complete check runs at the same time, on the job's thread, so that
//! its publish never waits for the syntax-only one (it only follows it on
//! the wire). The syntax-only result, computed on a second thread, is
//! dropped if the complete one was published before it is ready, or
//! before the wait `ROBOSIM_SYNTAX_HOLD_MS` after the job started (none by
//! default: see `state::syntax_hold`).
//!
//! The verification results about a file's assertions (`verify.rs`) are
//! published with its diagnostics, in both publishes. A publish computed
//! before those results changed is not sent: the change schedules another.

use std::sync::{Arc, Condvar, Mutex};
use std::time::Instant;

use robosim_ide::{Analysis, Cancellable, FileId, Verified};
use tower_lsp_server::ls_types::{self as lsp, Uri};

use crate::convert::{self, Text};
use crate::state::{Phase, Shared};

/// Starts diagnostics for `primary` (the file just changed), then, when
/// `others`, for every other file whose diagnostics may depend on it.
pub(crate) fn schedule(shared: &Arc<Shared>, primary: Option<(String, u64)>, others: bool) {
    // The load of the workspace folders ends with a pass over every file.
    if shared.lock().diagnostics_wait() {
        return;
    }
    let job = shared.clone();
    crate::background::spawn(shared, "robosim-engine", move || run(&job, primary, others));
    // Results of verification dropped by the change: titles to update.
    crate::verify::refresh_lenses(shared);
}

/// Publishes the diagnostics of `keys` again (their verification results
/// changed).
pub(crate) fn republish(shared: &Arc<Shared>, keys: Vec<String>) {
    let job = shared.clone();
    crate::background::spawn(shared, "robosim-republish", move || {
        let shared = job;
        for key in keys {
            let Some(seq) = shared.lock().files.get(&key).map(|e| e.seq) else { continue };
            full(&shared, &key, seq, false, false, None);
        }
    });
}

/// What a job needs to know about one file, read under the lock.
struct Target {
    key: String,
    seq: u64,
    uri: Uri,
    version: Option<i32>,
    file: Option<FileId>,
    /// The verification results about the file's assertions, and their
    /// stamp.
    verified: Vec<Verified>,
    stamp: u64,
}

#[derive(PartialEq, Eq)]
enum Outcome {
    /// The file changed since: a newer job takes over.
    Stale,
    Done,
}

/// Between the two publishes of one edit: whether the complete one has
/// been sent (or given up), so that the syntax-only one never follows it.
#[derive(Default)]
struct Gate {
    complete: Mutex<bool>,
    changed: Condvar,
}

impl Gate {
    /// Marks the complete publish as done (sent, or not needed).
    fn close(&self) {
        *self.complete.lock().unwrap_or_else(|e| e.into_inner()) = true;
        self.changed.notify_all();
    }
}

fn run(shared: &Arc<Shared>, primary: Option<(String, u64)>, others: bool) {
    if let Some((key, seq)) = &primary {
        let gate = Arc::new(Gate::default());
        let deadline = Instant::now() + shared.syntax_hold;
        let (job, fast_gate, fast_key, fast_seq) = (shared.clone(), gate.clone(), key.clone(), *seq);
        crate::background::spawn(shared, "robosim-syntax", move || {
            fast(&job, &fast_key, fast_seq, &fast_gate, deadline);
        });
        let outcome = full(shared, key, *seq, true, true, Some(&gate));
        gate.close();
        if outcome == Outcome::Stale {
            return;
        }
    }
    if !others {
        return;
    }
    let all = shared.lock().all_files();
    for (key, seq) in all {
        if primary.as_ref().is_some_and(|(k, _)| *k == key) {
            continue;
        }
        // A newer edit of the primary file makes this pass redundant.
        if let Some((pk, ps)) = &primary {
            if shared.lock().current(pk, *ps).is_none() {
                return;
            }
        }
        full(shared, &key, seq, false, false, None);
    }
}

/// The syntax-only publish for an edited buffer: parse only, older
/// semantic diagnostics carried over; sent unless the complete publish
/// passes `gate` before `deadline`. Nothing for files that are not open.
fn fast(shared: &Arc<Shared>, key: &str, seq: u64, gate: &Gate, deadline: Instant) -> Outcome {
    loop {
        if shared.phase() != Phase::Running {
            return Outcome::Stale;
        }
        let (analysis, target, carried) = {
            let st = shared.lock();
            let Some(entry) = st.current(key, seq) else { return Outcome::Stale };
            let (Some(doc), Some(file)) = (&entry.open, entry.file) else { return Outcome::Done };
            let carried = doc.checked.as_ref().map(|d| robosim_ide::carry_over(d, file, &doc.edits));
            let target = Target {
                key: key.to_string(),
                seq,
                uri: entry.uri.clone(),
                version: Some(doc.version),
                file: Some(file),
                verified: st.verify.reports_for(key),
                stamp: st.verify.stamp(key),
            };
            (st.host.analysis(), target, carried)
        };
        let result = target.file.map(|file| -> Cancellable<_> {
            let mut diags = analysis.syntax_diagnostics(file)?;
            diags.extend(carried.unwrap_or_default());
            if !target.verified.is_empty() {
                diags.extend(analysis.verify_diagnostics(file, &target.verified)?);
            }
            diags.sort_by_key(|d| (d.range.start(), d.range.end()));
            convert_all(&analysis, file, &diags)
        });
        drop(analysis);
        match result {
            Some(Ok(diags)) => {
                // No snapshot is held while waiting; the gate stays locked
                // while publishing, so the complete publish comes after.
                let mut complete = gate.complete.lock().unwrap_or_else(|e| e.into_inner());
                while !*complete {
                    let now = Instant::now();
                    if now >= deadline {
                        break;
                    }
                    complete = gate.changed.wait_timeout(complete, deadline - now).unwrap_or_else(|e| e.into_inner()).0;
                }
                if !*complete {
                    publish(shared, &target, diags, None, true);
                }
                return Outcome::Done;
            }
            Some(Err(_cancelled)) => continue,
            None => return Outcome::Done,
        }
    }
}

/// Computes and publishes one file's complete diagnostics, retrying when a
/// write that did not change this file cancelled the computation. With
/// `parallel` (the file just edited, whose check someone waits for), a
/// second thread computes part of the rules at the same time when the
/// buffer has no complete check yet. `gate`: the edit's syntax-only
/// publish, which must not follow this one.
fn full(shared: &Arc<Shared>, key: &str, seq: u64, force: bool, parallel: bool, gate: Option<&Gate>) -> Outcome {
    loop {
        if shared.phase() != Phase::Running {
            return Outcome::Stale;
        }
        let (analysis, target, first_check) = {
            let st = shared.lock();
            let Some(entry) = st.current(key, seq) else { return Outcome::Stale };
            let first_check = entry.open.as_ref().is_none_or(|d| d.checked.is_none());
            let target = Target {
                key: key.to_string(),
                seq,
                uri: entry.uri.clone(),
                version: entry.open.as_ref().map(|d| d.version),
                file: entry.file,
                verified: st.verify.reports_for(key),
                stamp: st.verify.stamp(key),
            };
            (st.host.analysis(), target, first_check)
        };
        // Only for a check from scratch: after an edit the rules of the
        // edited element are all there is to compute (they run per
        // element), and a second thread would only re-verify the other
        // elements' results alongside this one.
        if let (true, true, Some(file)) = (parallel, first_check, target.file) {
            // Its own snapshot, dropped when done or cancelled by an edit;
            // the results land in the shared memo tables.
            let helper = analysis.clone();
            crate::background::spawn(shared, "robosim-engine-rules", move || {
                let _ = helper.prefetch_diagnostics(file);
            });
        }
        let result = match target.file {
            Some(file) => analysis.diagnostics(file).and_then(|d| {
                if target.verified.is_empty() {
                    return Ok((convert_all(&analysis, file, &d)?, Some(d)));
                }
                // Kept apart from the check's own, which later edits carry.
                let mut all = d.clone();
                all.extend(analysis.verify_diagnostics(file, &target.verified)?);
                all.sort_by_key(|d| (d.range.start(), d.range.end()));
                Ok((convert_all(&analysis, file, &all)?, Some(d)))
            }),
            None => Ok((Vec::new(), None)),
        };
        drop(analysis);
        match result {
            Ok((diags, checked)) => {
                if let Some(gate) = gate {
                    // Taken after a syntax-only publish under way.
                    gate.close();
                }
                publish(shared, &target, diags, checked, force);
                return Outcome::Done;
            }
            // Loop: `current` above tells whether it was this file that
            // changed.
            Err(_cancelled) => continue,
        }
    }
}

/// The file's diagnostics in LSP form, positions converted against the
/// snapshot's own text.
fn convert_all(
    analysis: &Analysis,
    file: FileId,
    diags: &[robosim_ide::Diagnostic],
) -> Cancellable<Vec<lsp::Diagnostic>> {
    if diags.is_empty() {
        return Ok(Vec::new());
    }
    let text = analysis.file_text(file)?;
    let index = analysis.line_index(file)?;
    let t = Text { text: &text, index: &index };
    let mut out = Vec::with_capacity(diags.len());
    for d in diags {
        let mut related = Vec::new();
        for r in &d.related {
            // Locations in the bundled library have no URI to show.
            let Some(uri) = uri_from_key(&r.path) else { continue };
            let other_text = analysis.file_text(r.file)?;
            let other_index = analysis.line_index(r.file)?;
            let o = Text { text: &other_text, index: &other_index };
            related.push(lsp::DiagnosticRelatedInformation {
                location: lsp::Location::new(uri, o.range(r.range)),
                message: r.message.clone(),
            });
        }
        out.push(convert::diagnostic(t, d, related));
    }
    Ok(out)
}

/// The URI of a file key, without the state: keys of `file:` URIs are
/// absolute paths, others are URIs.
pub(crate) fn uri_from_key(key: &str) -> Option<Uri> {
    if std::path::Path::new(key).is_absolute() {
        crate::state::uri_of_path(std::path::Path::new(key))
    } else {
        key.parse().ok()
    }
}

/// Publishes `diags` if the file is still at the target's `seq`. `checked`
/// is the complete result behind them, kept to be carried over later
/// edits.
fn publish(
    shared: &Arc<Shared>,
    target: &Target,
    diags: Vec<lsp::Diagnostic>,
    checked: Option<Vec<robosim_ide::Diagnostic>>,
    force: bool,
) {
    let Some(client) = shared.client().cloned() else { return };
    // Held across the check and the send: a publish for an older `seq`
    // either goes out before this one or sees that it is stale.
    let _order = shared.publish.lock().unwrap_or_else(|e| e.into_inner());
    // After `shutdown` the client expects nothing more.
    if shared.phase() != Phase::Running {
        return;
    }
    {
        let mut st = shared.lock();
        // Newer verification results: the publish they scheduled covers it.
        if st.verify.stamp(&target.key) != target.stamp {
            return;
        }
        let Some(entry) = st.files.get_mut(&target.key).filter(|e| e.seq == target.seq) else { return };
        if let (Some(doc), Some(checked)) = (entry.open.as_mut(), checked) {
            doc.checked = Some(checked);
            doc.edits.clear();
        }
        let unchanged = match st.published.get(&target.key) {
            Some((v, d)) => *v == target.version && *d == diags,
            // Nothing to clear either.
            None => diags.is_empty(),
        };
        // A removed file's diagnostics are always cleared: the client may
        // hold some from before this server knew the file.
        if !force && unchanged && target.file.is_some() {
            return;
        }
        st.published.insert(target.key.clone(), (target.version, diags.clone()));
    }
    shared.runtime.block_on(client.publish_diagnostics(target.uri.clone(), diags, target.version));
    if target.file.is_none() {
        // Cleared: the entry of a removed file has served its purpose.
        let mut st = shared.lock();
        if st.current(&target.key, target.seq).is_some_and(|e| e.file.is_none() && e.open.is_none()) {
            st.files.remove(&target.key);
            st.published.remove(&target.key);
        }
    }
}
