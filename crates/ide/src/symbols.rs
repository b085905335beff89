//! Declarations as an outline (document symbols) and as a searchable flat
//! list over the workspace (workspace symbols). Purely syntactic: every
//! declaration the parser recognised, named or not, recovery included.

use robosim_hir::{Db, File, Workspace};
use robosim_syntax::ast::{self, AstNode};
use robosim_syntax::{SyntaxKind, SyntaxKind::*, SyntaxNode, TextRange};

use crate::FileId;

/// What a declaration declares. Shared by the outline and highlighting.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum SymbolKind {
    /// `package a::b`.
    Package,
    /// `interface I`.
    Interface,
    /// `robotic platform P`, or `rref p = P`.
    Platform,
    /// `controller C`, or `cref c = C`.
    Controller,
    /// `module M`.
    Module,
    /// `stm M`, or `sref m = M`.
    StateMachine,
    /// An operation definition, signature or `opref`.
    Operation,
    /// `function f(…) : T`.
    Function,
    /// `type T`.
    PrimitiveType,
    /// `record R` / `datatype R`.
    Record,
    /// A record field.
    Field,
    /// `enumeration E`.
    Enum,
    /// An enumeration literal.
    EnumLiteral,
    /// `event e`.
    Event,
    /// `var x`.
    Variable,
    /// `const k`.
    Constant,
    /// `clock C`.
    Clock,
    /// An operation or function parameter.
    Parameter,
    /// `state S`.
    State,
    /// `initial i`.
    Initial,
    /// `junction j`.
    Junction,
    /// `final f`.
    Final,
    /// `probabilistic p`.
    ProbabilisticJunction,
    /// `transition t`.
    Transition,
    /// `assertion A : …`.
    Assertion,
    /// `csp P csp-begin … csp-end`.
    CspProcess,
    /// `simulation S of M` (RoboSim assertions).
    Simulation,
}

impl SymbolKind {
    /// A lower-case description ("state machine", …).
    pub fn describe(self) -> &'static str {
        match self {
            SymbolKind::Package => "package",
            SymbolKind::Interface => "interface",
            SymbolKind::Platform => "robotic platform",
            SymbolKind::Controller => "controller",
            SymbolKind::Module => "module",
            SymbolKind::StateMachine => "state machine",
            SymbolKind::Operation => "operation",
            SymbolKind::Function => "function",
            SymbolKind::PrimitiveType => "type",
            SymbolKind::Record => "record",
            SymbolKind::Field => "field",
            SymbolKind::Enum => "enumeration",
            SymbolKind::EnumLiteral => "enumeration literal",
            SymbolKind::Event => "event",
            SymbolKind::Variable => "variable",
            SymbolKind::Constant => "constant",
            SymbolKind::Clock => "clock",
            SymbolKind::Parameter => "parameter",
            SymbolKind::State => "state",
            SymbolKind::Initial => "initial junction",
            SymbolKind::Junction => "junction",
            SymbolKind::Final => "final state",
            SymbolKind::ProbabilisticJunction => "probabilistic junction",
            SymbolKind::Transition => "transition",
            SymbolKind::Assertion => "assertion",
            SymbolKind::CspProcess => "CSP process",
            SymbolKind::Simulation => "simulation",
        }
    }

    /// The kind of the declaration whose `NAME` child has parent `node`.
    /// `None` for nodes that declare nothing.
    pub(crate) fn of_declaration(node: &SyntaxNode) -> Option<SymbolKind> {
        Some(match node.kind() {
            PACKAGE_DECL | DIAGRAM_DECL => SymbolKind::Package,
            INTERFACE => SymbolKind::Interface,
            ROBOTIC_PLATFORM | PLATFORM_REF => SymbolKind::Platform,
            CONTROLLER | CONTROLLER_REF => SymbolKind::Controller,
            MODULE => SymbolKind::Module,
            STATE_MACHINE | STATE_MACHINE_REF => SymbolKind::StateMachine,
            OPERATION_DEF | OPERATION_SIG | OPERATION_REF => SymbolKind::Operation,
            FUNCTION => SymbolKind::Function,
            PRIMITIVE_TYPE_DECL => SymbolKind::PrimitiveType,
            RECORD_DECL => SymbolKind::Record,
            FIELD => SymbolKind::Field,
            ENUM_DECL => SymbolKind::Enum,
            ENUM_LITERAL => SymbolKind::EnumLiteral,
            EVENT => SymbolKind::Event,
            VARIABLE => {
                let is_const = node.parent().and_then(ast::VariableList::cast).is_some_and(|l| l.is_const());
                if is_const {
                    SymbolKind::Constant
                } else {
                    SymbolKind::Variable
                }
            }
            CLOCK => SymbolKind::Clock,
            PARAM => SymbolKind::Parameter,
            STATE => SymbolKind::State,
            INITIAL => SymbolKind::Initial,
            JUNCTION => SymbolKind::Junction,
            FINAL => SymbolKind::Final,
            PROBABILISTIC_JUNCTION => SymbolKind::ProbabilisticJunction,
            TRANSITION => SymbolKind::Transition,
            ASSERTION | PROB_PROPERTY | PROB_CONSTANTS => SymbolKind::Assertion,
            PROB_CONST => SymbolKind::Constant,
            CSP_BLOCK => SymbolKind::CspProcess,
            SIMULATION => SymbolKind::Simulation,
            _ => return None,
        })
    }
}

/// One declaration of the outline.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct DocumentSymbol {
    /// The declared name (`<unnamed>` when the source lacks it).
    pub name: String,
    /// A short summary: the type, the parameters, `from → to`, the target
    /// of a reference.
    pub detail: Option<String>,
    /// What it declares.
    pub kind: SymbolKind,
    /// The whole declaration.
    pub full_range: TextRange,
    /// The name (or, when unnamed, the declaration's first token).
    pub selection_range: TextRange,
    /// Nested declarations, in source order.
    pub children: Vec<DocumentSymbol>,
}

/// One declaration found by a workspace search.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct WorkspaceSymbol {
    /// The declared name.
    pub name: String,
    /// What it declares.
    pub kind: SymbolKind,
    /// The name of the enclosing declaration, if any.
    pub container_name: Option<String>,
    /// The file.
    pub file: FileId,
    /// Its path.
    pub path: String,
    /// The whole declaration.
    pub full_range: TextRange,
    /// The name.
    pub selection_range: TextRange,
}

const UNNAMED: &str = "<unnamed>";

/// The outline of a file, memoised per version of its text.
#[salsa::tracked(returns(ref))]
pub(crate) fn document_symbols(db: &dyn Db, file: File) -> Vec<DocumentSymbol> {
    let root = robosim_hir::parse(db, file).syntax_node();
    let mut out = Vec::new();
    collect(&root, &mut out);
    out
}

/// Collects the declarations among the children of `node` (descending
/// through nodes that group declarations without declaring anything).
fn collect(node: &SyntaxNode, out: &mut Vec<DocumentSymbol>) {
    for child in node.children() {
        match child.kind() {
            VARIABLE_LIST | INPUT_CONTEXT | OUTPUT_CONTEXT | ERROR => collect(&child, out),
            PACKAGE_DECL => {
                if let Some(q) = child.children().find_map(ast::QualifiedName::cast) {
                    out.push(DocumentSymbol {
                        name: q.text(),
                        detail: None,
                        kind: SymbolKind::Package,
                        full_range: child.text_range(),
                        selection_range: q.syntax().text_range(),
                        children: Vec::new(),
                    });
                }
            }
            // Parameters are part of the signature shown as the detail;
            // the outline stays readable without them.
            PARAM | DIAGRAM_DECL => {}
            _ => {
                if let Some(kind) = SymbolKind::of_declaration(&child) {
                    out.push(symbol(&child, kind));
                }
            }
        }
    }
}

fn symbol(node: &SyntaxNode, kind: SymbolKind) -> DocumentSymbol {
    let name = node.children().find_map(ast::Name::cast);
    let selection_range = match &name {
        Some(n) => n.syntax().text_range(),
        None => node
            .children_with_tokens()
            .find(|e| !e.kind().is_trivia())
            .map(|e| e.text_range())
            .unwrap_or_else(|| node.text_range()),
    };
    let name = name.map(|n| n.text()).filter(|n| !n.is_empty()).unwrap_or_else(|| UNNAMED.to_string());
    let mut children = Vec::new();
    if has_members(node.kind()) {
        collect(node, &mut children);
    }
    DocumentSymbol { name, detail: detail(node), kind, full_range: node.text_range(), selection_range, children }
}

/// Declarations whose body holds further declarations.
fn has_members(kind: SyntaxKind) -> bool {
    matches!(
        kind,
        INTERFACE
            | ROBOTIC_PLATFORM
            | CONTROLLER
            | MODULE
            | STATE_MACHINE
            | OPERATION_DEF
            | STATE
            | RECORD_DECL
            | ENUM_DECL
            | SIMULATION
    )
}

/// The source text of `node` on one line, shortened.
fn one_line(node: &SyntaxNode) -> String {
    let text = node.text().to_string();
    let mut s = text.split_whitespace().collect::<Vec<_>>().join(" ");
    if s.chars().count() > 80 {
        s = s.chars().take(79).collect::<String>() + "…";
    }
    s
}

fn type_of(node: &SyntaxNode) -> Option<SyntaxNode> {
    node.children().find(|n| ast::is_type_kind(n.kind()))
}

fn detail(node: &SyntaxNode) -> Option<String> {
    match node.kind() {
        EVENT | VARIABLE | FIELD => type_of(node).map(|t| one_line(&t)),
        OPERATION_SIG | OPERATION_DEF => node.children().find(|n| n.kind() == PARAM_LIST).map(|p| one_line(&p)),
        FUNCTION => {
            let params = node.children().find(|n| n.kind() == PARAM_LIST).map(|p| one_line(&p)).unwrap_or_default();
            let ret = type_of(node).map(|t| format!(" : {}", one_line(&t))).unwrap_or_default();
            Some(format!("{params}{ret}"))
        }
        TRANSITION => {
            let t = ast::Transition::cast(node.clone())?;
            let from = t.source().map(|n| n.text()).unwrap_or_else(|| "?".into());
            let to = t.target().map(|n| n.text()).unwrap_or_else(|| "?".into());
            Some(format!("{from} → {to}"))
        }
        PLATFORM_REF | CONTROLLER_REF | STATE_MACHINE_REF | OPERATION_REF => {
            node.children().find_map(ast::QualifiedName::cast).map(|q| format!("= {}", q.text()))
        }
        SIMULATION => ast::Simulation::cast(node.clone())?.of().map(|q| format!("of {}", q.text())),
        ASSERTION => ast::Assertion::cast(node.clone())?.subject().map(|q| q.text()),
        _ => None,
    }
}

/// How well `name` matches `query` (lower-cased): smaller is better.
fn match_rank(name: &str, query: &str) -> Option<u8> {
    if query.is_empty() {
        return Some(3);
    }
    let lower = name.to_lowercase();
    if lower == query {
        Some(0)
    } else if lower.starts_with(query) {
        Some(1)
    } else if lower.contains(query) {
        Some(2)
    } else {
        // The characters of the query in order, as in `stmov` for
        // `StmMovement`: what editors' fuzzy pickers users expect.
        let mut chars = lower.chars();
        query.chars().all(|q| chars.any(|c| c == q)).then_some(3)
    }
}

pub(crate) fn workspace_symbols(db: &dyn Db, workspace: Workspace, query: &str, limit: usize) -> Vec<WorkspaceSymbol> {
    let query = query.trim().to_lowercase();
    let mut found: Vec<(u8, bool, WorkspaceSymbol)> = Vec::new();
    for &file in workspace.files(db) {
        crate::check_cancelled(db);
        let path = file.path(db);
        let is_library = file.is_library(db);
        let mut stack: Vec<(&DocumentSymbol, Option<&str>)> =
            document_symbols(db, file).iter().rev().map(|s| (s, None)).collect();
        while let Some((sym, container)) = stack.pop() {
            if sym.name != UNNAMED {
                if let Some(rank) = match_rank(&sym.name, &query) {
                    found.push((
                        rank,
                        is_library,
                        WorkspaceSymbol {
                            name: sym.name.clone(),
                            kind: sym.kind,
                            container_name: container.map(str::to_string),
                            file: FileId(file),
                            path: path.clone(),
                            full_range: sym.full_range,
                            selection_range: sym.selection_range,
                        },
                    ));
                }
            }
            stack.extend(sym.children.iter().rev().map(|c| (c, Some(sym.name.as_str()))));
        }
    }
    // User files before the library at equal rank: they are what people
    // are looking for. Then shorter (closer) names first.
    found.sort_by(|(ra, la, a), (rb, lb, b)| {
        (ra, la, a.name.len(), &a.name, &a.path, a.full_range.start()).cmp(&(
            rb,
            lb,
            b.name.len(),
            &b.name,
            &b.path,
            b.full_range.start(),
        ))
    });
    found.into_iter().take(limit).map(|(_, _, s)| s).collect()
}
