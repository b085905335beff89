//! The standard library every RoboChart and RoboSim model sees without
//! importing it: the primitive types of `core`, the set, sequence, relation
//! and function toolkits, and RoboSim's `exec` event. Written for this
//! project (the signatures follow RoboTool's library so that models resolve
//! the same names) and bundled in the binary, so no library path is needed.

/// One bundled library file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LibFile {
    /// A virtual path, shown in diagnostics and hovers (`<stdlib>/core.rct`).
    pub path: &'static str,
    /// The file's text.
    pub text: &'static str,
}

macro_rules! lib_files {
    ($($name:literal),* $(,)?) => {
        &[$(LibFile { path: concat!("<stdlib>/", $name), text: include_str!(concat!("../lib/", $name)) }),*]
    };
}

/// Every bundled library file.
pub const FILES: &[LibFile] = lib_files![
    "core.rct",
    "set_toolkit.rct",
    "sequence_toolkit.rct",
    "relation_toolkit.rct",
    "function_toolkit.rct",
    "robosim_core.rst",
];

/// Whether `path` names a bundled library file.
pub fn is_stdlib_path(path: &str) -> bool {
    path.starts_with("<stdlib>/")
}

#[cfg(test)]
mod tests {
    use super::*;
    use robosim_syntax::{parse, FileKind};

    #[test]
    fn every_library_file_parses_without_errors() {
        for f in FILES {
            let kind = FileKind::from_extension(f.path.rsplit('.').next().unwrap()).unwrap();
            let p = parse(f.text, kind);
            assert!(p.errors().is_empty(), "{}: {:?}", f.path, p.errors());
            assert_eq!(p.syntax_node().text().to_string(), f.text);
        }
    }

    #[test]
    fn core_declares_the_primitive_types() {
        let core = FILES.iter().find(|f| f.path.ends_with("core.rct")).unwrap();
        let p = parse(core.text, FileKind::RoboChart);
        let names: Vec<String> = p
            .tree()
            .items()
            .filter_map(|i| match i {
                robosim_syntax::ast::Item::PrimitiveType(t) => {
                    use robosim_syntax::ast::HasName;
                    t.name().map(|n| n.text())
                }
                _ => None,
            })
            .collect();
        for t in ["nat", "int", "real", "boolean", "string"] {
            assert!(names.iter().any(|n| n == t), "core lacks {t}: {names:?}");
        }
    }
}
