//! Completion. A cheap reading of the position decides what fits, from
//! the token before the name being typed and the enclosing nodes:
//!
//! - after `$` (RoboSim): the machine's inputs in expressions and its
//!   outputs at the start of a statement;
//! - after `from`/`to` of a transition: the nodes of its container; after
//!   `connection`/`to` of a connection: its nodes; after `trigger`: events;
//!   after `on` in a connection: the events of the node before it;
//! - after `uses`/`provides`/`requires`: interfaces; after `:` in a
//!   declaration: types; after `sref x =` (and `cref`, `rref`, `opref`):
//!   machines (controllers, platforms, operations); after `E::`: the
//!   literals of `E`; after `#` and `since(`: clocks;
//! - where an operand is expected (after `=`, an operator, `(`, `entry`,
//!   `condition`, …): the variables, constants and parameters in scope,
//!   functions and enumerations, and a few expression keywords; at the start
//!   of a statement also events (RoboChart), operations and statement
//!   keywords;
//! - after a declaration keyword (`state`, `var`, …): nothing, a new name
//!   comes next;
//! - elsewhere: the keywords that may start a member of the enclosing block
//!   (file, machine, state, transition, …) in the file's language.

use robosim_hir::defs::{DefId, DefKind, Io, UseKind};
use robosim_hir::index::{file_summary, index_for, resolve_item};
use robosim_hir::nav::type_ref_text;
use robosim_hir::resolve::{ctx_members, enclosing, node_ctx, Ctx, Member, MEMBER_CONTEXTS};
use robosim_hir::{Db, File, Workspace};
use robosim_syntax::{FileKind, SyntaxKind, SyntaxKind::*, SyntaxNode, SyntaxToken, TextRange, TextSize};

use crate::hover::prev_significant;
use crate::navigation::symbol_kind;
use crate::symbols::SymbolKind;

/// What a completion inserts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum CompletionKind {
    /// A reserved word (or two, as `input context`).
    Keyword,
    /// A declared name.
    Symbol(SymbolKind),
}

/// One completion.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct CompletionItem {
    /// The text shown and inserted.
    pub label: String,
    /// What it is.
    pub kind: CompletionKind,
    /// More about it (`input event : nat`, …).
    pub detail: Option<String>,
    /// The range the insertion replaces: the part of the name already
    /// typed before the cursor.
    pub range: TextRange,
}

fn is_ident_byte(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b == b'_'
}

struct Acc {
    kind: FileKind,
    range: TextRange,
    items: Vec<CompletionItem>,
}

impl Acc {
    fn keyword(&mut self, kw: &str) {
        if kw.split(' ').all(|w| SyntaxKind::keyword(w, self.kind).is_some()) {
            self.items.push(CompletionItem {
                label: kw.to_string(),
                kind: CompletionKind::Keyword,
                detail: None,
                range: self.range,
            });
        }
    }

    fn keywords(&mut self, kws: &[&str]) {
        for kw in kws {
            self.keyword(kw);
        }
    }

    fn symbol(&mut self, name: &str, kind: DefKind, detail: Option<String>) {
        if name.is_empty() {
            return;
        }
        self.items.push(CompletionItem {
            label: name.to_string(),
            kind: CompletionKind::Symbol(symbol_kind(kind)),
            detail,
            range: self.range,
        });
    }

    fn member(&mut self, m: &Member, io_label: bool) {
        let mut detail = String::new();
        if io_label {
            detail.push_str(match m.io {
                Some(Io::Input) => "input ",
                Some(Io::Output) => "output ",
                None => "",
            });
        }
        detail.push_str(m.kind.describe());
        if let Some(t) = &m.ty {
            detail.push_str(" : ");
            detail.push_str(&type_ref_text(t));
        }
        if m.kind == DefKind::OperationSig {
            detail = format!("{detail} {}({})", m.name, m.params.join(", "));
        }
        self.symbol(&m.name, m.kind, Some(detail));
    }
}

pub(crate) fn completions(db: &dyn Db, ws: Workspace, file: File, offset: TextSize) -> Vec<CompletionItem> {
    if let Some(items) = crate::csp_block::completions(db, ws, file, offset) {
        return items;
    }
    let text = file.text(db);
    let mut offset = usize::from(offset).min(text.len());
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    let bytes = text.as_bytes();
    let mut start = offset;
    while start > 0 && is_ident_byte(bytes[start - 1]) {
        start -= 1;
    }
    if bytes.get(start).is_some_and(|b| b.is_ascii_digit()) && start < offset {
        return Vec::new(); // a number
    }
    let (start, offset) = (TextSize::from(start as u32), TextSize::from(offset as u32));
    let root = robosim_hir::parse(db, file).syntax_node();
    if in_comment_or_string(&root, offset) {
        return Vec::new();
    }
    let mut acc = Acc { kind: file.kind(db), range: TextRange::new(start, offset), items: Vec::new() };
    let prev = prev_token(&root, start);
    let c = Cx { db, ws, file, root: &root, start, offset };
    match &prev {
        Some(p) => c.after(p, &mut acc),
        None => c.block_keywords(None, &mut acc),
    }
    let mut items = acc.items;
    items.sort_by(|a, b| (a.kind, &a.label).cmp(&(b.kind, &b.label)));
    items.dedup_by(|a, b| a.label == b.label && a.kind == b.kind);
    items
}

/// Whether `offset` lies inside a comment, a string or a CSP block.
fn in_comment_or_string(root: &SyntaxNode, offset: TextSize) -> bool {
    let inside = |t: &SyntaxToken| {
        let r = t.text_range();
        let strictly = r.start() < offset && offset < r.end();
        // At the end of a line comment without its line break (end of file),
        // or of an unterminated block comment or string.
        let at_open_end = r.end() == offset
            && match t.kind() {
                LINE_COMMENT => !t.text().ends_with('\n'),
                BLOCK_COMMENT => !t.text().ends_with("*/") || t.text().len() < 4,
                STRING => t.text().len() < 2 || !t.text().ends_with(&t.text()[..1]),
                _ => false,
            };
        matches!(t.kind(), LINE_COMMENT | BLOCK_COMMENT | STRING | CSP_TEXT) && (strictly || at_open_end)
    };
    root.token_at_offset(offset).any(|t| inside(&t))
}

/// The last non-trivia token that ends at or before `start`.
fn prev_token(root: &SyntaxNode, start: TextSize) -> Option<SyntaxToken> {
    let mut t = root.token_at_offset(start).left_biased();
    while let Some(x) = t {
        if x.text_range().end() <= start && !x.kind().is_trivia() {
            return Some(x);
        }
        t = x.prev_token();
    }
    None
}

/// Keywords after which a new name is declared.
const DECLARING: &[SyntaxKind] = &[
    STATE_KW,
    VAR_KW,
    CONST_KW,
    EVENT_KW,
    STM_KW,
    INTERFACE_KW,
    TRANSITION_KW,
    INITIAL_KW,
    JUNCTION_KW,
    FINAL_KW,
    CLOCK_KW,
    CONTROLLER_KW,
    MODULE_KW,
    OPERATION_KW,
    FUNCTION_KW,
    TYPE_KW,
    RECORD_KW,
    DATATYPE_KW,
    ENUMERATION_KW,
    PACKAGE_KW,
    IMPORT_KW,
    SREF_KW,
    CREF_KW,
    RREF_KW,
    OPREF_KW,
    PLATFORM_KW,
    PROBABILISTIC_KW,
    ASSERTION_KW,
    SIMULATION_KW,
    CSP_KW,
    BROADCAST_KW,
];

/// Tokens after which an operand (an expression, or a statement) comes.
const OPERAND_BEFORE: &[SyntaxKind] = &[
    EQ,
    EQ2,
    NEQ,
    LT,
    LTEQ,
    GT,
    GTEQ,
    PLUS,
    MINUS,
    STAR,
    SLASH,
    PERCENT,
    AND,
    OR,
    IMPLIES,
    L_PAREN,
    L_BRACK,
    COMMA,
    BANG,
    QUESTION,
    NOT_KW,
    IF_KW,
    THEN_KW,
    ELSE_KW,
    IFF_KW,
    ENTRY_KW,
    DURING_KW,
    EXIT_KW,
    ACTION_KW,
    CONDITION_KW,
    PROBABILITY_KW,
    CYCLE_DEF_KW,
    SEMI,
    AT,
    COLON,
    PRECONDITION_KW,
    POSTCONDITION_KW,
];

/// Tokens after which a statement starts.
const STATEMENT_BEFORE: &[SyntaxKind] = &[ENTRY_KW, DURING_KW, EXIT_KW, ACTION_KW, SEMI];

/// Block kinds, for member keywords.
const BLOCKS: &[SyntaxKind] = &[
    STATE_MACHINE,
    STATE,
    OPERATION_DEF,
    CONTROLLER,
    MODULE,
    INTERFACE,
    ROBOTIC_PLATFORM,
    TRANSITION,
    INPUT_CONTEXT,
    OUTPUT_CONTEXT,
    FUNCTION,
    RECORD_DECL,
    ENUM_DECL,
    SIMULATION,
];

/// Where an operand goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Position {
    /// The start of a statement (an action).
    Statement,
    /// An expression in a transition condition.
    Condition,
    /// Any other expression.
    Expression,
}

struct Cx<'a> {
    db: &'a dyn Db,
    ws: Workspace,
    file: File,
    root: &'a SyntaxNode,
    start: TextSize,
    offset: TextSize,
}

impl<'a> Cx<'a> {
    fn after(&self, prev: &SyntaxToken, acc: &mut Acc) {
        let parent = prev.parent().map(|p| p.kind());
        let in_node = |k: SyntaxKind| prev.parent_ancestors().any(|a| a.kind() == k);
        let nearest = |kinds: &[SyntaxKind]| prev.parent_ancestors().find(|a| kinds.contains(&a.kind()));
        match prev.kind() {
            DOLLAR => self.dollar(prev, acc),
            FROM_KW | TO_KW if nearest(&[TRANSITION, CONNECTION]).is_some_and(|n| n.kind() == TRANSITION) => {
                self.transition_ends(acc)
            }
            TO_KW | CONNECTION_KW if in_node(CONNECTION) => self.connection_nodes(acc),
            ON_KW if in_node(CONNECTION) => self.connection_events(prev, acc),
            TRIGGER_KW => self.events(acc),
            USES_KW | PROVIDES_KW | REQUIRES_KW => self.items(acc, |k| k == DefKind::Interface),
            COLON
                if matches!(
                    parent,
                    Some(VARIABLE | EVENT | PARAM | FIELD | FUNCTION | VARIABLE_LIST | OPERATION_SIG | BINDER)
                ) =>
            {
                self.items(acc, DefKind::is_type)
            }
            EQ if matches!(parent, Some(STATE_MACHINE_REF)) => self.items(acc, |k| k == DefKind::StateMachine),
            EQ if matches!(parent, Some(CONTROLLER_REF)) => self.items(acc, |k| k == DefKind::Controller),
            EQ if matches!(parent, Some(PLATFORM_REF)) => self.items(acc, |k| k == DefKind::Platform),
            EQ if matches!(parent, Some(OPERATION_REF)) => self.items(acc, |k| k == DefKind::Operation),
            COLON2 => self.enum_literals(prev, acc),
            HASH => self.clocks(acc),
            L_PAREN if matches!(parent, Some(SINCE_EXPR | SINCE_ENTRY_EXPR)) => {
                if parent == Some(SINCE_EXPR) {
                    self.clocks(acc)
                } else {
                    self.states(acc)
                }
            }
            COMMA if matches!(parent, Some(VARIABLE_LIST)) => {} // `var a, b`: a new name
            k if DECLARING.contains(&k) => {}
            L_CURLY if parent.is_some_and(|p| BLOCKS.contains(&p)) => self.block_keywords(Some(prev), acc),
            k if k == CYCLE_DEF_KW || (OPERAND_BEFORE.contains(&k) && in_node(CYCLE_DEF)) => self.cycle_operands(acc),
            k if OPERAND_BEFORE.contains(&k) || k == L_CURLY => {
                let position =
                    if STATEMENT_BEFORE.contains(&k) || (matches!(k, THEN_KW | ELSE_KW) && parent == Some(IF_STMT)) {
                        Position::Statement
                    } else if k == CONDITION_KW || in_node(CONDITION) {
                        Position::Condition
                    } else {
                        Position::Expression
                    };
                self.operands(position, acc);
            }
            _ => self.block_keywords(Some(prev), acc),
        }
    }

    /// The definitions around the cursor (those of the element there:
    /// right after a keystroke, the file's are not put together again).
    fn defs(&self) -> &'a robosim_hir::defs::FileDefs {
        robosim_hir::element::defs_around(self.db, self.file, TextRange::empty(self.start))
    }

    /// The definition whose members names at the cursor see.
    fn context(&self, kinds: &[DefKind]) -> Option<DefId> {
        let defs = self.defs();
        let inner = defs.innermost(TextRange::empty(self.start))?;
        enclosing(defs, inner, kinds)
    }

    fn members(&self, kinds: &[DefKind]) -> Vec<Member> {
        match self.context(kinds) {
            Some(ctx) => ctx_members(self.db, self.ws, Ctx::Local(self.file, ctx)).into_owned(),
            None => Vec::new(),
        }
    }

    fn dollar(&self, dollar: &SyntaxToken, acc: &mut Acc) {
        if self.file.kind(self.db) != FileKind::RoboSim {
            return;
        }
        // At the start of a statement, `$` writes an output; elsewhere it
        // reads an input.
        let before = prev_significant(dollar);
        let statement = before.as_ref().is_some_and(|b| {
            STATEMENT_BEFORE.contains(&b.kind())
                || (matches!(b.kind(), THEN_KW | ELSE_KW) && b.parent().is_some_and(|p| p.kind() == IF_STMT))
        });
        let wanted = if statement { Io::Output } else { Io::Input };
        for m in self.members(&[DefKind::Operation, DefKind::StateMachine]) {
            let fits = match wanted {
                Io::Input => m.io == Some(Io::Input) && matches!(m.kind, DefKind::Event | DefKind::Variable),
                Io::Output => m.io == Some(Io::Output),
            };
            if fits {
                acc.member(&m, true);
            }
        }
    }

    fn transition_ends(&self, acc: &mut Acc) {
        let defs = self.defs();
        let Some(inner) = defs.innermost(TextRange::empty(self.start)) else { return };
        let Some(t) = enclosing(defs, inner, &[DefKind::Transition]) else { return };
        let Some(container) = defs.def(t).parent else { return };
        for (_, n) in defs.children(Some(container)) {
            if n.kind.is_node() {
                acc.symbol(&n.name, n.kind, Some(n.kind.describe().to_string()));
            }
        }
    }

    fn connection_owner(&self) -> Option<DefId> {
        self.context(&[DefKind::Controller, DefKind::Module])
    }

    fn connection_nodes(&self, acc: &mut Acc) {
        let Some(owner) = self.connection_owner() else { return };
        let defs = self.defs();
        let od = defs.def(owner);
        if od.kind == DefKind::Controller {
            acc.symbol(&od.name, od.kind, Some("this controller".to_string()));
        }
        for (_, n) in defs.children(Some(owner)) {
            if matches!(
                n.kind,
                DefKind::Controller
                    | DefKind::ControllerRef
                    | DefKind::StateMachine
                    | DefKind::MachineRef
                    | DefKind::Platform
                    | DefKind::PlatformRef
            ) {
                acc.symbol(&n.name, n.kind, Some(n.kind.describe().to_string()));
            }
        }
    }

    fn connection_events(&self, on: &SyntaxToken, acc: &mut Acc) {
        // The node is the name just before `on`.
        let Some(node) = prev_significant(on) else { return };
        let name = node.text().trim_start_matches('^');
        let Some(owner) = self.connection_owner() else { return };
        let defs = self.defs();
        let ctx = if defs.def(owner).name == name {
            Some(Ctx::Local(self.file, owner))
        } else {
            defs.children(Some(owner))
                .find(|(_, n)| n.name == name)
                .and_then(|(id, _)| node_ctx(self.db, self.ws, self.file, id))
        };
        let Some(ctx) = ctx else { return };
        for m in ctx_members(self.db, self.ws, ctx).into_owned() {
            if m.kind == DefKind::Event {
                acc.member(&m, false);
            }
        }
    }

    fn events(&self, acc: &mut Acc) {
        for m in self.members(&[DefKind::StateMachine, DefKind::Operation, DefKind::Controller]) {
            if m.kind == DefKind::Event {
                acc.member(&m, false);
            }
        }
    }

    fn clocks(&self, acc: &mut Acc) {
        for m in self.members(&[DefKind::StateMachine, DefKind::Operation]) {
            if m.kind == DefKind::Clock && m.via != Some(UseKind::Provides) {
                acc.member(&m, false);
            }
        }
    }

    fn states(&self, acc: &mut Acc) {
        let defs = self.defs();
        let Some(owner) = self.context(&[DefKind::StateMachine, DefKind::Operation]) else { return };
        for (id, d) in defs.iter() {
            if d.kind == DefKind::State
                && enclosing(defs, id, &[DefKind::StateMachine, DefKind::Operation]) == Some(owner)
            {
                acc.symbol(&d.name, d.kind, Some("state".to_string()));
            }
        }
    }

    /// The items of the workspace visible from this file whose kind passes
    /// `accept`.
    fn items(&self, acc: &mut Acc, accept: fn(DefKind) -> bool) {
        let index = index_for(self.db, self.ws, self.file);
        let here = file_summary(self.db, self.file);
        for (full, locs) in &index.items {
            let Some((name, pkg)) = full.split_last() else { continue };
            let visible = pkg == here.package.as_slice()
                || pkg.is_empty()
                || pkg == ["core"]
                || (pkg == ["robosim__core"] && self.file.kind(self.db) == FileKind::RoboSim)
                || here
                    .imports
                    .iter()
                    .any(|(p, w)| (*w && p.as_slice() == pkg) || (!*w && p.as_slice() == full.as_slice()));
            if !visible {
                continue;
            }
            if let Some(l) = locs.iter().find(|l| accept(l.summary(self.db).kind)) {
                let kind = l.summary(self.db).kind;
                let detail = if pkg.is_empty() {
                    kind.describe().to_string()
                } else {
                    format!("{} in {}", kind.describe(), pkg.join("::"))
                };
                acc.symbol(name, kind, Some(detail));
            }
        }
    }

    fn enum_literals(&self, colons: &SyntaxToken, acc: &mut Acc) {
        let Some(name) = prev_significant(colons) else { return };
        if name.kind() != IDENT {
            return;
        }
        let path = [name.text().trim_start_matches('^').to_string()];
        let Some(loc) =
            resolve_item(self.db, self.ws, self.file, &path, |k| k == DefKind::Enumeration).first().copied()
        else {
            return;
        };
        for m in &loc.summary(self.db).members {
            if m.kind == DefKind::EnumLiteral {
                acc.symbol(&m.name, m.kind, Some(format!("literal of {}", path[0])));
            }
        }
    }

    /// A cycle specification mentions only `cycle`, literals and constants.
    fn cycle_operands(&self, acc: &mut Acc) {
        acc.keywords(&["cycle", "true", "false", "not"]);
        for m in self.members(&[DefKind::StateMachine, DefKind::Controller, DefKind::Module]) {
            if m.kind == DefKind::Constant {
                acc.member(&m, false);
            }
        }
    }

    /// Names usable as operands, and at the start of a statement also
    /// events, operations and statement keywords.
    fn operands(&self, position: Position, acc: &mut Acc) {
        let rs = self.file.kind(self.db) == FileKind::RoboSim;
        let statement = position == Position::Statement;
        if let Some(ctx) = self.context(MEMBER_CONTEXTS) {
            for m in ctx_members(self.db, self.ws, Ctx::Local(self.file, ctx)).into_owned() {
                // RoboSim inputs and outputs are written with `$`.
                if rs && m.io.is_some() {
                    continue;
                }
                let fits = match m.kind {
                    DefKind::Variable | DefKind::Constant => true,
                    DefKind::Event => statement && !rs,
                    DefKind::OperationSig => statement && m.via != Some(UseKind::Uses),
                    _ => false,
                };
                if fits {
                    acc.member(&m, false);
                }
            }
            let defs = self.defs();
            for (_, p) in defs.children(Some(ctx)) {
                if p.kind == DefKind::Parameter {
                    acc.symbol(&p.name, p.kind, Some("parameter".to_string()));
                }
            }
        }
        self.items(acc, |k| matches!(k, DefKind::Function | DefKind::Enumeration));
        match position {
            Position::Statement => acc.keywords(&["if", "wait", "skip"]),
            Position::Expression => acc.keywords(&["true", "false", "not"]),
            // Timed expressions belong in conditions, not actions (RC:TE1).
            Position::Condition => acc.keywords(&["true", "false", "not", "since", "sinceEntry"]),
        }
    }

    /// Keywords that may start a member of the innermost open block.
    fn block_keywords(&self, prev: Option<&SyntaxToken>, acc: &mut Acc) {
        let block = prev.and_then(|p| p.parent_ancestors().find(|n| BLOCKS.contains(&n.kind()) && self.open(n)));
        let Some(block) = block else {
            // The top level.
            if self.file.kind(self.db).is_assertions() {
                acc.keywords(&["import", "assertion", "csp", "simulation"]);
            } else {
                let has_package = self.root.children().any(|c| c.kind() == PACKAGE_DECL);
                if !has_package && prev.is_none() {
                    acc.keyword("package");
                }
                acc.keywords(&[
                    "import",
                    "interface",
                    "robotic platform",
                    "type",
                    "datatype",
                    "record",
                    "enumeration",
                    "controller",
                    "stm",
                    "operation",
                    "function",
                    "module",
                ]);
            }
            return;
        };
        const NODES: &[&str] = &["state", "initial", "junction", "final", "probabilistic", "transition"];
        match block.kind() {
            STATE_MACHINE => {
                acc.keywords(&["uses", "requires", "var", "const", "event", "clock", "cycleDef"]);
                acc.keywords(&["input context", "output context"]);
                acc.keywords(NODES);
            }
            OPERATION_DEF => {
                acc.keywords(&["terminates", "precondition", "postcondition", "uses", "requires", "var", "const"]);
                acc.keywords(&["event", "clock", "input context", "output context"]);
                acc.keywords(NODES);
            }
            STATE => {
                acc.keywords(&["entry", "during", "exit"]);
                acc.keywords(NODES);
            }
            CONTROLLER => acc.keywords(&[
                "uses",
                "provides",
                "requires",
                "var",
                "const",
                "event",
                "operation",
                "opref",
                "stm",
                "sref",
                "connection",
                "cycleDef",
            ]),
            MODULE => acc.keywords(&["robotic platform", "rref", "controller", "cref", "connection", "cycleDef"]),
            INTERFACE => acc.keywords(&["event", "var", "const", "clock"]),
            ROBOTIC_PLATFORM => acc.keywords(&["uses", "provides", "event", "var", "const"]),
            INPUT_CONTEXT | OUTPUT_CONTEXT => acc.keywords(&["uses", "requires", "event"]),
            FUNCTION => acc.keywords(&["precondition", "postcondition"]),
            TRANSITION => {
                let has = |k: SyntaxKind| block.children().any(|c| c.kind() == k);
                if !has(TRANSITION_SOURCE) {
                    acc.keyword("from");
                } else if !has(TRANSITION_TARGET) {
                    acc.keyword("to");
                } else {
                    if !has(TRIGGER) && !has(EXEC_TRIGGER) {
                        acc.keywords(&["trigger", "exec"]);
                    }
                    if !has(PROBABILITY) {
                        acc.keyword("probability");
                    }
                    if !has(CONDITION) {
                        acc.keyword("condition");
                    }
                    if !has(TRANSITION_ACTION) {
                        acc.keyword("action");
                    }
                }
            }
            _ => {}
        }
    }

    /// Whether the body of `block` is open at the cursor: its `{` is before
    /// it and its `}` (if any) after.
    fn open(&self, block: &SyntaxNode) -> bool {
        let tokens = || block.children_with_tokens().filter_map(|e| e.into_token());
        let Some(l) = tokens().find(|t| t.kind() == L_CURLY) else { return false };
        if l.text_range().end() > self.start {
            return false;
        }
        match tokens().filter(|t| t.kind() == R_CURLY).last() {
            Some(r) => r.text_range().start() >= self.offset,
            None => true,
        }
    }
}
