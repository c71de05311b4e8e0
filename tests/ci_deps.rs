//! `.ci/deps` detects libclang by the file names bindgen can load, never by `libclang-cpp`.
//!
//! Debian's stock image ships `libclang-cpp14` (the C++ interface library) without libclang
//! itself; a detection that counted it skipped the install and the HiGHS build panicked in
//! bindgen. These tests source the script and run its `have_libclang` against temporary
//! directory trees.

use std::path::Path;
use std::process::Command;

/// Runs `have_libclang` with the search directories replaced by `dirs`; true when it finds one.
fn have_libclang(dirs: &[&Path], libclang_path: Option<&Path>) -> bool {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join(".ci/deps");
    let joined = dirs
        .iter()
        .map(|d| d.display().to_string())
        .collect::<Vec<_>>()
        .join(":");
    let mut cmd = Command::new("bash");
    cmd.arg("-c")
        .arg("source \"$1\" && have_libclang")
        .arg("bash")
        .arg(&script)
        .env("PUSHPACK_DEPS_NO_MAIN", "1")
        .env("PUSHPACK_LIBCLANG_DIRS", joined)
        .env_remove("LIBCLANG_PATH");
    if let Some(p) = libclang_path {
        cmd.env("LIBCLANG_PATH", p);
    }
    let out = cmd.output().expect("bash runs");
    assert!(
        out.status.code().is_some_and(|c| c <= 1),
        "have_libclang must answer 0 or 1, got {:?}: {}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    out.status.success()
}

fn tree(files: &[&str]) -> tempfile::TempDir {
    let dir = tempfile::tempdir().expect("temp dir");
    for f in files {
        std::fs::write(dir.path().join(f), b"").expect("write");
    }
    dir
}

#[test]
fn libclang_cpp_alone_is_not_libclang() {
    let d = tree(&["libclang-cpp.so.14", "libclangAST.a", "libLLVM-14.so.1"]);
    assert!(!have_libclang(&[d.path()], None));
}

#[test]
fn an_empty_tree_has_no_libclang() {
    let d = tree(&[]);
    assert!(!have_libclang(&[d.path()], None));
}

#[test]
fn every_name_bindgen_loads_counts() {
    for name in [
        "libclang.so",
        "libclang.so.1",
        "libclang-14.so",
        "libclang-14.so.1",
        "libclang-14.so.14.0.6",
    ] {
        let d = tree(&["libclang-cpp.so.14", name]);
        assert!(have_libclang(&[d.path()], None), "{name} must count as libclang");
    }
}

#[test]
fn any_searched_directory_may_hold_it() {
    let (a, b) = (tree(&["libclang-cpp.so.14"]), tree(&["libclang.so.1"]));
    assert!(have_libclang(&[a.path(), b.path()], None));
}

#[test]
fn libclang_path_is_honoured_and_checked() {
    let (empty, real, cpp) = (tree(&[]), tree(&["libclang.so"]), tree(&["libclang-cpp.so.14"]));
    assert!(have_libclang(&[empty.path()], Some(real.path())));
    assert!(!have_libclang(&[empty.path()], Some(cpp.path())));
}
