//! The RoboChart/RoboSim language server: LSP over stdio, on
//! `tower-lsp-server` and tokio, with every feature computed by
//! `robosim-ide`. This is the only crate that knows LSP types.
//!
//! How edits stay ordered and results fresh follows lsp-ecosystem.md §1.1:
//!
//! - document notifications are applied in wire order, under one lock,
//!   before anything awaits (`ordered.rs`), and the version is stored with
//!   the text (`state.rs`);
//! - diagnostics are computed on blocking threads from snapshots, and
//!   published only if their version is still current, under a lock that
//!   keeps publishes in order (`diagnostics.rs`);
//! - a new edit cancels older computations through salsa.
//!
//! The transport (`transport.rs`) is our own loop around tower-lsp-server's
//! `LspService`, because the crate's own transport stops reading after the
//! first malformed message.

mod background;
mod convert;
mod diagnostics;
mod diagram;
mod ordered;
mod server;
mod state;
mod transport;
mod verify;
mod workspace;

use std::process::ExitCode;
use std::sync::atomic::Ordering;
use std::sync::Arc;

use tower_lsp_server::LspService;

use crate::ordered::Ordered;
use crate::server::Backend;
use crate::state::Shared;

/// Runs the server on stdin/stdout until `exit` or the end of input.
/// Exit status 0 after `shutdown` then `exit`, 1 otherwise (as LSP says).
pub fn run_stdio() -> ExitCode {
    // Analyses recurse over the syntax tree, whose nesting the parser caps
    // at 384 levels; 16 MB stacks leave a wide margin over what that needs
    // (the default of 2 MB does not, in debug builds). The memory is only
    // reserved, not used.
    let runtime = match tokio::runtime::Builder::new_multi_thread().thread_stack_size(16 << 20).enable_all().build() {
        Ok(rt) => rt,
        Err(e) => {
            eprintln!("robosim lsp: cannot start the async runtime: {e}");
            return ExitCode::from(2);
        }
    };
    let shared = Shared::new(runtime.handle().clone());
    runtime.block_on(serve(tokio::io::stdin(), tokio::io::stdout(), shared.clone()));
    // Work still running on blocking threads (a check started by the last
    // edit) is abandoned: the client has gone.
    runtime.shutdown_background();
    if shared.shutdown_requested.load(Ordering::SeqCst) {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}

async fn serve<I, O>(input: I, output: O, shared: Arc<Shared>)
where
    I: tokio::io::AsyncRead + Unpin,
    O: tokio::io::AsyncWrite + Unpin + Send + 'static,
{
    let backend_shared = shared.clone();
    let (inner, socket) = LspService::build(move |client| Backend::new(client, backend_shared))
        .custom_method(diagram::METHOD, Backend::diagram)
        .finish();
    let service = Ordered { inner, shared };
    transport::serve(input, output, service, socket).await;
}
