//! Document synchronisation in wire order.
//!
//! tower-lsp-server runs handler futures concurrently (up to four at a
//! time), so a `didChange` handler could overtake the one before it. But it
//! calls the service's `call` once per message, in the order read, inside
//! its read loop. This adapter applies `didOpen`, `didChange` and
//! `didClose` right there, synchronously, before anything can await, and
//! hands every other message to the inner service (lsp-ecosystem.md §1.1,
//! "strongest option").

use std::future::Future;
use std::pin::Pin;
use std::sync::Arc;
use std::task::{Context, Poll};

use serde::de::DeserializeOwned;
use tower::Service;
use tower_lsp_server::jsonrpc::{Request, Response};
use tower_lsp_server::ls_types::{
    DidChangeTextDocumentParams, DidCloseTextDocumentParams, DidOpenTextDocumentParams, MessageType,
    WorkDoneProgressCancelParams,
};
use tower_lsp_server::{ExitedError, LspService};

use crate::server::Backend;
use crate::state::{Phase, Shared};
use crate::{diagnostics, workspace};

type BoxFuture = Pin<Box<dyn Future<Output = Result<Option<Response>, ExitedError>> + Send>>;

/// The service the transport drives: document sync here, the rest in the
/// inner `LspService`.
pub(crate) struct Ordered {
    pub(crate) inner: LspService<Backend>,
    pub(crate) shared: Arc<Shared>,
}

impl Service<Request> for Ordered {
    type Response = Option<Response>;
    type Error = ExitedError;
    type Future = BoxFuture;

    fn poll_ready(&mut self, cx: &mut Context<'_>) -> Poll<Result<(), Self::Error>> {
        self.inner.poll_ready(cx)
    }

    fn call(&mut self, req: Request) -> Self::Future {
        let sync = matches!(req.method(), "textDocument/didOpen" | "textDocument/didChange" | "textDocument/didClose");
        // Notifications only: a request with one of these names is a client
        // error that the inner service answers.
        if sync && req.id().is_none() && self.shared.phase() == Phase::Running {
            apply(&self.shared, req);
            return Box::pin(std::future::ready(Ok(None)));
        }
        if req.method() == "window/workDoneProgress/cancel" && req.id().is_none() {
            // tower-lsp-server has no handler for it.
            if self.shared.phase() == Phase::Running {
                cancel_progress(&self.shared, req);
            }
            return Box::pin(std::future::ready(Ok(None)));
        }
        if req.method() == "shutdown" && req.id().is_some() && self.shared.phase() == Phase::Running {
            // Edits after `shutdown` are ignored from this very message on,
            // not from whenever the handler happens to run.
            self.shared.set_phase(Phase::ShutDown);
            self.shared.shutdown_requested.store(true, std::sync::atomic::Ordering::SeqCst);
        }
        self.inner.call(req)
    }
}

fn params<T: DeserializeOwned>(shared: &Shared, method: &str, params: Option<serde_json::Value>) -> Option<T> {
    match serde_json::from_value(params.unwrap_or(serde_json::Value::Null)) {
        Ok(p) => Some(p),
        Err(e) => {
            shared.log(MessageType::ERROR, format!("ignored `{method}` with invalid parameters: {e}"));
            None
        }
    }
}

/// `window/workDoneProgress/cancel`: stops the verification job that
/// reports under the token, if any.
fn cancel_progress(shared: &Arc<Shared>, req: Request) {
    let (method, _, raw) = req.into_parts();
    let Some(p) = params::<WorkDoneProgressCancelParams>(shared, method.as_ref(), raw) else { return };
    shared.lock().verify.cancel_token(&p.token);
}

/// Applies one document notification to the state, then starts the
/// diagnostics for the result. Never panics, whatever the parameters.
fn apply(shared: &Arc<Shared>, req: Request) {
    let (method, _, raw) = req.into_parts();
    let method = method.as_ref();
    match method {
        "textDocument/didOpen" => {
            let Some(p) = params::<DidOpenTextDocumentParams>(shared, method, raw) else { return };
            let applied = shared.lock().open(p.text_document);
            for w in &applied.warnings {
                shared.log(MessageType::WARNING, w.clone());
            }
            diagnostics::schedule(shared, Some((applied.key, applied.seq)), true);
        }
        "textDocument/didChange" => {
            let Some(p) = params::<DidChangeTextDocumentParams>(shared, method, raw) else { return };
            let uri = p.text_document.uri.clone();
            let applied = shared.lock().change(p);
            match applied {
                Some(applied) => {
                    for w in &applied.warnings {
                        shared.log(MessageType::WARNING, w.clone());
                    }
                    diagnostics::schedule(shared, Some((applied.key, applied.seq)), true);
                }
                None => shared
                    .log(MessageType::WARNING, format!("ignored a change to `{}`, which is not open", uri.as_str())),
            }
        }
        _ => {
            let Some(p) = params::<DidCloseTextDocumentParams>(shared, method, raw) else { return };
            let uri = p.text_document.uri;
            let closed = shared.lock().close(&uri);
            match closed {
                // The disk text takes over from the buffer: read it back.
                Some((applied, true)) => workspace::reload_from_disk(shared, applied.key),
                // Gone from the workspace: clear its diagnostics.
                Some((applied, false)) => diagnostics::schedule(shared, Some((applied.key, applied.seq)), true),
                None => {
                    shared.log(MessageType::WARNING, format!("ignored closing `{}`, which is not open", uri.as_str()))
                }
            }
        }
    }
}
