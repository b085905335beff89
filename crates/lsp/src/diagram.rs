//! Diagrams in the editor: the `robosim/diagram` request and the
//! "◇ Show diagram" code lenses.
//!
//! `robosim/diagram` takes `{ textDocument: { uri }, element?: string }` and
//! answers `{ uri, diagrams: [{ model, svg }] }`: the diagram model of each
//! state machine, operation, controller and module of the document (the
//! JSON of `robosim diagram --json`), or of the one named `element` (a name
//! or a qualified name), with its SVG. An element the document does not
//! declare, like a document the server does not know, is an error
//! (`InvalidParams`).
//!
//! The lenses run `robosim.showDiagram` with `[uri, qualified name]`, a
//! command that the client runs itself (it opens a view and sends
//! `robosim/diagram`): the server does not list it in
//! `executeCommandProvider`, and gives the lenses only to clients that
//! declare it among their commands, as rust-analyzer's clients do
//! (`capabilities.experimental.commands.commands`).

use robosim_ide::{DiagramLens, RenderedDiagram};
use serde::{Deserialize, Serialize};
use serde_json::Value;
use tower_lsp_server::jsonrpc::{Error, ErrorCode, Result};
use tower_lsp_server::ls_types::{ClientCapabilities, CodeLens, Command, Range, TextDocumentIdentifier, Uri};

use crate::convert::Text;
use crate::server::{text_of, Backend};

/// The custom request.
pub(crate) const METHOD: &str = "robosim/diagram";

/// The client-side command of the lenses.
pub(crate) const COMMAND: &str = "robosim.showDiagram";

/// The title of the lenses.
pub(crate) const LENS_TITLE: &str = "◇ Show diagram";

/// The parameters of `robosim/diagram`.
#[derive(Debug, Deserialize)]
#[serde(rename_all = "camelCase")]
pub(crate) struct DiagramParams {
    /// The document.
    pub(crate) text_document: TextDocumentIdentifier,
    /// A name or qualified name; every diagram of the document when absent.
    #[serde(default)]
    pub(crate) element: Option<String>,
}

/// One diagram of the answer.
#[derive(Debug, Serialize)]
struct DiagramItem {
    /// The model, as `robosim diagram --json` prints it.
    model: robosim_ide::diagram::Diagram,
    /// The SVG document.
    svg: String,
}

/// The answer of `robosim/diagram`.
#[derive(Debug, Serialize)]
struct DiagramResult {
    uri: Uri,
    diagrams: Vec<DiagramItem>,
}

/// Whether the client runs `robosim.showDiagram` itself: it lists it in
/// `experimental.commands.commands`.
pub(crate) fn client_shows_diagrams(c: &ClientCapabilities) -> bool {
    c.experimental
        .as_ref()
        .and_then(|e| e.get("commands"))
        .and_then(|c| c.get("commands"))
        .and_then(Value::as_array)
        .is_some_and(|list| list.iter().any(|c| c.as_str() == Some(COMMAND)))
}

/// The lens of `lens`, in `uri`.
pub(crate) fn code_lens(uri: &Uri, range: Range, lens: &DiagramLens) -> CodeLens {
    CodeLens {
        range,
        command: Some(Command {
            title: LENS_TITLE.to_string(),
            command: COMMAND.to_string(),
            arguments: Some(vec![Value::String(uri.as_str().to_string()), Value::String(lens.qualified_name.clone())]),
        }),
        data: None,
    }
}

/// The diagram lenses of a file, with their LSP ranges.
pub(crate) fn lenses(
    a: &robosim_ide::Analysis,
    file: robosim_ide::FileId,
) -> robosim_ide::Cancellable<Vec<(Range, DiagramLens)>> {
    let lenses = a.diagram_lenses(file)?;
    if lenses.is_empty() {
        return Ok(Vec::new());
    }
    let (text, index) = text_of(a, file)?;
    let t = Text { text: &text, index: &index };
    Ok(lenses.into_iter().map(|l| (t.range(l.range), l)).collect())
}

impl Backend {
    /// `robosim/diagram`.
    pub(crate) async fn diagram(&self, params: DiagramParams) -> Result<Value> {
        let uri = params.text_document.uri;
        let element = params.element;
        let found = self
            .with_file(&uri, move |a, file, _| {
                let rendered = a.diagrams(file, element.as_deref())?;
                Ok(rendered.map_err(|e| e.to_string()))
            })
            .await?;
        let diagrams =
            found.map_err(|message| Error { code: ErrorCode::InvalidParams, message: message.into(), data: None })?;
        // After a failed check, its counterexample is drawn on the diagrams
        // it passes through.
        let counterexamples = self.shared.lock().verify.counterexamples();
        let diagrams: Vec<RenderedDiagram> = if counterexamples.is_empty() {
            diagrams
        } else {
            diagrams.into_iter().map(|r| robosim_ide::diagram::render_with(r.diagram, &counterexamples)).collect()
        };
        let result = DiagramResult {
            uri,
            diagrams: diagrams.into_iter().map(|r| DiagramItem { model: r.diagram, svg: r.svg }).collect(),
        };
        serde_json::to_value(result).map_err(|e| Error {
            code: ErrorCode::InternalError,
            message: format!("cannot serialise the diagrams: {e}").into(),
            data: None,
        })
    }
}
