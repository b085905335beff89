//! End-to-end tests of `robosim fmt [--check] PATH...`: what is rewritten,
//! what is only reported, and the exit codes (0 clean, 1 would change or
//! syntax errors, 2 usage and I/O problems).

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn robosim() -> Command {
    Command::new(env!("CARGO_BIN_EXE_robosim-e2e"))
}

/// A fresh folder under the system's temporary folder, removed on drop.
struct TempDir(PathBuf);

impl TempDir {
    fn new(name: &str) -> TempDir {
        let dir = std::env::temp_dir().join(format!("robosim-fmt-{}-{name}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        TempDir(dir)
    }

    fn write(&self, rel: &str, text: impl AsRef<[u8]>) -> PathBuf {
        let p = self.0.join(rel);
        fs::create_dir_all(p.parent().unwrap()).unwrap();
        fs::write(&p, text).unwrap();
        p
    }

    /// Every file under the folder, relative, sorted.
    fn files(&self) -> Vec<String> {
        fn walk(dir: &Path, root: &Path, out: &mut Vec<String>) {
            for e in fs::read_dir(dir).unwrap().flatten() {
                let p = e.path();
                if p.is_dir() {
                    walk(&p, root, out);
                } else {
                    out.push(p.strip_prefix(root).unwrap().to_string_lossy().replace('\\', "/"));
                }
            }
        }
        let mut out = Vec::new();
        walk(&self.0, &self.0, &mut out);
        out.sort();
        out
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = fs::remove_dir_all(&self.0);
    }
}

const FORMATTED: &str = "interface I {\n    event e\n}\n";
const UNFORMATTED: &str = "interface   I{event e}\n\n\n\nstm M{initial i}";
const UNFORMATTED_FIXED: &str = "interface I { event e }\n\nstm M { initial i }\n";
const RSA: &str = "simulation S of M{cycleDef cycle==1}\nassertion A:S is schedulable";
const RSA_FIXED: &str = "simulation S of M { cycleDef cycle == 1 }\nassertion A : S is schedulable\n";
const BROKEN: &str = "stm M {\n  state S { entry x = 1; }\n}\n";
const REST: &str = "Title\n=====\n\n.. note:: not a model\n";

fn stdout(o: &Output) -> String {
    String::from_utf8(o.stdout.clone()).unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8(o.stderr.clone()).unwrap()
}

/// A project with one formatted, two unformatted and one broken model, plus
/// files `fmt` must leave alone.
fn project(name: &str) -> TempDir {
    let t = TempDir::new(name);
    t.write("good.rct", FORMATTED);
    t.write("bad.rct", UNFORMATTED);
    t.write("sub/deep/sim.rsa", RSA);
    t.write("broken.rct", BROKEN);
    t.write("docs/index.rst", REST);
    t.write("notes.txt", "interface   I{}");
    t.write(".hidden/x.rct", UNFORMATTED);
    t
}

#[test]
fn check_lists_files_and_changes_nothing() {
    let t = project("check");
    let before: Vec<_> = t.files().iter().map(|f| fs::read(t.0.join(f)).unwrap()).collect();
    let out = robosim().args(["fmt", "--check"]).arg(&t.0).output().unwrap();
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let want = format!(
        "would reformat: {}\nwould reformat: {}\n",
        t.0.join("bad.rct").display(),
        t.0.join("sub/deep/sim.rsa").display()
    );
    assert_eq!(stdout(&out), want);
    assert_eq!(
        stderr(&out).trim(),
        format!(
            "robosim: {}: not formatted: 2:24: `;` separates statements and cannot end them: remove this `;`",
            t.0.join("broken.rct").display()
        )
    );
    let after: Vec<_> = t.files().iter().map(|f| fs::read(t.0.join(f)).unwrap()).collect();
    assert_eq!(before, after, "--check must not write");

    // Formatted files only: nothing to say, exit 0.
    let out = robosim().args(["fmt", "--check"]).arg(t.0.join("good.rct")).output().unwrap();
    assert_eq!(out.status.code(), Some(0));
    assert_eq!(stdout(&out), "");
    assert_eq!(stderr(&out), "");
}

#[test]
fn rewrite_in_place() {
    let t = project("rewrite");
    let out = robosim().arg("fmt").arg(&t.0).output().unwrap();
    // The broken file makes the status 1, the others are still formatted.
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert_eq!(stdout(&out), "formatted 2 files, 1 unchanged\n");
    assert!(stderr(&out).contains("broken.rct: not formatted: 2:24:"), "{}", stderr(&out));
    assert_eq!(fs::read_to_string(t.0.join("good.rct")).unwrap(), FORMATTED);
    assert_eq!(fs::read_to_string(t.0.join("bad.rct")).unwrap(), UNFORMATTED_FIXED);
    assert_eq!(fs::read_to_string(t.0.join("sub/deep/sim.rsa")).unwrap(), RSA_FIXED);
    assert_eq!(fs::read_to_string(t.0.join("broken.rct")).unwrap(), BROKEN);
    // Skipped: documentation, other extensions, hidden folders. No
    // temporary file is left behind.
    assert_eq!(fs::read_to_string(t.0.join("docs/index.rst")).unwrap(), REST);
    assert_eq!(fs::read_to_string(t.0.join(".hidden/x.rct")).unwrap(), UNFORMATTED);
    assert_eq!(
        t.files(),
        [".hidden/x.rct", "bad.rct", "broken.rct", "docs/index.rst", "good.rct", "notes.txt", "sub/deep/sim.rsa"]
    );

    // A second run finds nothing to do.
    fs::remove_file(t.0.join("broken.rct")).unwrap();
    let out = robosim().arg("fmt").arg(&t.0).output().unwrap();
    assert_eq!(out.status.code(), Some(0));
    assert_eq!(stdout(&out), "formatted 0 files, 3 unchanged\n");
    let out = robosim().args(["fmt", "--check"]).arg(&t.0).output().unwrap();
    assert_eq!(out.status.code(), Some(0));
}

#[test]
fn single_files_and_singular_summary() {
    let t = TempDir::new("single");
    let a = t.write("a.rct", UNFORMATTED);
    // A `.rst` file named explicitly is always RoboSim.
    let b = t.write("b.rst", "stm M{initial i}");
    let out = robosim().arg("fmt").arg(&a).output().unwrap();
    assert_eq!(out.status.code(), Some(0));
    assert_eq!(stdout(&out), "formatted 1 file, 0 unchanged\n");
    let out = robosim().arg("fmt").arg(&b).arg(&a).output().unwrap();
    assert_eq!(stdout(&out), "formatted 1 file, 1 unchanged\n");
    assert_eq!(fs::read_to_string(&b).unwrap(), "stm M { initial i }\n");
}

#[test]
fn usage_and_io_errors_exit_2() {
    let t = TempDir::new("usage");
    let missing = t.0.join("no/such/file.rct");
    let out = robosim().arg("fmt").arg(&missing).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(stderr(&out).trim(), format!("robosim: cannot read `{}`: no such file or directory", missing.display()));
    let txt = t.write("notes.txt", "x");
    let out = robosim().arg("fmt").arg(&txt).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("is not a model file"), "{}", stderr(&out));
    let out = robosim().arg("fmt").output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    let out = robosim().args(["fmt", "--bogus", "x.rct"]).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn invalid_utf8_is_refused_and_kept() {
    let t = TempDir::new("utf8");
    let bytes = b"interface   I { event e }\n\xff\xfe junk";
    let f = t.write("bin.rct", bytes);
    let out = robosim().arg("fmt").arg(&f).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr(&out).contains("not formatted: the file is not valid UTF-8 text"), "{}", stderr(&out));
    assert_eq!(fs::read(&f).unwrap(), bytes);
}

#[test]
fn crlf_files_stay_crlf() {
    let t = TempDir::new("crlf");
    let f = t.write("w.rct", "interface I {\r\n  event e\r\n}");
    let out = robosim().arg("fmt").arg(&f).output().unwrap();
    assert_eq!(out.status.code(), Some(0));
    assert_eq!(fs::read_to_string(&f).unwrap(), "interface I {\r\n    event e\r\n}\r\n");
}

#[cfg(unix)]
#[test]
fn permissions_symlinks_and_read_only_files() {
    use std::os::unix::fs::PermissionsExt;
    let t = TempDir::new("unix");
    let f = t.write("m.rct", UNFORMATTED);
    fs::set_permissions(&f, fs::Permissions::from_mode(0o640)).unwrap();
    let out = robosim().arg("fmt").arg(&f).output().unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(fs::metadata(&f).unwrap().permissions().mode() & 0o777, 0o640);

    // Through a link, the target is rewritten and the link stays a link.
    let target = t.write("real/target.rct", UNFORMATTED);
    let link = t.0.join("link.rct");
    std::os::unix::fs::symlink(&target, &link).unwrap();
    let out = robosim().arg("fmt").arg(&link).output().unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(fs::symlink_metadata(&link).unwrap().file_type().is_symlink());
    assert_eq!(fs::read_to_string(&target).unwrap(), UNFORMATTED_FIXED);

    // A read-only file is not replaced: an I/O error, status 2.
    let ro = t.write("ro.rct", UNFORMATTED);
    fs::set_permissions(&ro, fs::Permissions::from_mode(0o444)).unwrap();
    let out = robosim().arg("fmt").arg(&ro).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains(&format!("cannot write `{}`", ro.display())), "{}", stderr(&out));
    assert_eq!(fs::read_to_string(&ro).unwrap(), UNFORMATTED);
    // --check only reads, so a read-only file is fine.
    let out = robosim().args(["fmt", "--check"]).arg(&ro).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    fs::set_permissions(&ro, fs::Permissions::from_mode(0o644)).unwrap();
}
