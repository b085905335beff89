//! Rename: the declaration and every reference to it, across the
//! workspace, or a refusal that says why.

use robosim_hir::defs::{file_defs, DefKind};
use robosim_hir::index::index_for;
use robosim_hir::nav::{DeclLoc, Symbol};
use robosim_hir::resolve::{ctx_members, Ctx};
use robosim_hir::{Db, File, Workspace};
use robosim_syntax::{FileKind, SyntaxKind, TextRange, TextSize};

use crate::edit::{SourceChange, TextEdit};
use crate::navigation::{decl_at, last_segment, references_of, trimmed};

/// Why a rename is refused; the message is for the user.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct RenameError(pub String);

impl std::fmt::Display for RenameError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for RenameError {}

fn err<T>(msg: impl Into<String>) -> Result<T, RenameError> {
    Err(RenameError(msg.into()))
}

fn language(kind: FileKind) -> &'static str {
    match kind {
        FileKind::RoboChart => "RoboChart",
        FileKind::RoboSim => "RoboSim",
        FileKind::Assertions => "RoboChart assertions",
        FileKind::SimAssertions => "RoboSim assertions",
    }
}

/// The declaration to rename at `offset`, and the range of the name under
/// the cursor.
fn renameable(db: &dyn Db, ws: Workspace, file: File, offset: TextSize) -> Result<(TextRange, DeclLoc), RenameError> {
    let text = file.text(db);
    let Some((sym, decl)) = decl_at(db, ws, file, offset) else {
        return err("there is no name to rename here");
    };
    let range = match &sym {
        Symbol::Reference(r) => last_segment(text, r.range),
        Symbol::Declaration(d) => trimmed(text, d.name_range),
    };
    let written = text.get(usize::from(range.start())..usize::from(range.end())).unwrap_or("");
    let Some(decl) = decl else {
        return err(format!("`{written}` does not resolve to a declaration, so there is nothing to rename"));
    };
    let d = file_defs(db, decl.file).def(decl.def);
    if d.name.is_empty() || d.kind == DefKind::Connection {
        return err("this declaration has no name to rename");
    }
    if decl.file.is_library(db) {
        return err(format!(
            "`{}` is declared in the bundled library (`{}`), which cannot be edited",
            d.name,
            decl.file.path(db)
        ));
    }
    Ok((range, decl))
}

pub(crate) fn prepare_rename(
    db: &dyn Db,
    ws: Workspace,
    file: File,
    offset: TextSize,
) -> Result<(TextRange, String), RenameError> {
    let (range, decl) = renameable(db, ws, file, offset)?;
    let name = file_defs(db, decl.file).def(decl.def).name.clone();
    Ok((range, name))
}

/// Whether `name` is an identifier of the model languages.
fn is_identifier(name: &str) -> bool {
    let mut chars = name.bytes();
    chars.next().is_some_and(|b| b.is_ascii_alphabetic() || b == b'_')
        && chars.all(|b| b.is_ascii_alphanumeric() || b == b'_')
}

pub(crate) fn rename(
    db: &dyn Db,
    ws: Workspace,
    file: File,
    offset: TextSize,
    new_name: &str,
) -> Result<SourceChange, RenameError> {
    let (_, decl) = renameable(db, ws, file, offset)?;
    let defs = file_defs(db, decl.file);
    let d = defs.def(decl.def);
    if !is_identifier(new_name) {
        return err(format!(
            "`{new_name}` is not a valid name: a name starts with a letter or `_` and continues with letters, digits and `_`"
        ));
    }
    if new_name == d.name {
        return Ok(SourceChange::default());
    }
    let refs = references_of(db, ws, decl, true);
    let files: Vec<File> = refs.iter().map(|r| r.file.0).collect();
    if let Some(lib) = files.iter().find(|f| f.is_library(db)) {
        return err(format!(
            "`{}` is used in the bundled library (`{}`), which cannot be edited",
            d.name,
            lib.path(db)
        ));
    }
    let mut kinds: Vec<FileKind> = files.iter().map(|f| f.kind(db)).collect();
    kinds.dedup();
    for kind in kinds {
        if SyntaxKind::keyword(new_name, kind).is_some() {
            return err(format!("`{new_name}` is a reserved word in {}", language(kind)));
        }
    }
    // Another declaration of that name in the same place.
    let clash = defs.children(d.parent).find(|(id, o)| *id != decl.def && o.name == new_name);
    if let Some((_, o)) = clash {
        let place = match d.parent {
            Some(p) => {
                let pd = defs.def(p);
                format!("{} `{}`", pd.kind.describe(), pd.name)
            }
            None => "this file".to_string(),
        };
        return err(format!("{place} already declares {} `{new_name}`", article(o.kind.describe())));
    }
    // Members brought in by interfaces share the context's names.
    if let Some(p) = d.parent {
        if matches!(
            d.kind,
            DefKind::Event | DefKind::Variable | DefKind::Constant | DefKind::Clock | DefKind::OperationSig
        ) {
            if let Some(m) = ctx_members(db, ws, Ctx::Local(decl.file, p)).iter().find(|m| m.name == new_name) {
                let pd = defs.def(p);
                return err(format!(
                    "{} `{}` already has {} `{new_name}`",
                    pd.kind.describe(),
                    pd.name,
                    article(m.kind.describe())
                ));
            }
        }
    }
    // Top-level items share their package with the other files'.
    if d.parent.is_none() && d.kind.is_item() {
        let mut path = defs.package.clone();
        path.push(new_name.to_string());
        if let Some(other) = index_for(db, ws, decl.file).items.get(&path).and_then(|v| v.first()) {
            let pkg = if defs.package.is_empty() {
                "the default package".to_string()
            } else {
                format!("package `{}`", defs.package.join("::"))
            };
            return err(format!(
                "{pkg} already has {} `{new_name}` (in `{}`)",
                article(other.summary(db).kind.describe()),
                other.file.path(db)
            ));
        }
    }
    let mut change = SourceChange::default();
    for r in refs {
        change.push(r.file, &r.path, TextEdit::replace(r.range, new_name));
    }
    Ok(change.finish())
}

fn article(what: &str) -> String {
    let an = what.starts_with(['a', 'e', 'i', 'o', 'u']);
    format!("{} {what}", if an { "an" } else { "a" })
}
