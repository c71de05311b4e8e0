//! Build script: embeds the git commit (PUSHPACK_GIT_COMMIT) so benchmark results say which code
//! produced them. Never fails: without git or outside a repository the commit is `unknown`.

use std::process::Command;

fn git(args: &[&str]) -> Option<String> {
    let out = Command::new("git").args(args).output().ok()?;
    if !out.status.success() {
        return None;
    }
    let s = String::from_utf8(out.stdout).ok()?.trim().to_string();
    (!s.is_empty()).then_some(s)
}

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    let commit = git(&["rev-parse", "--short=12", "HEAD"]).unwrap_or_else(|| "unknown".into());
    // Rebuild when HEAD moves: HEAD itself (branch switch), the branch's ref file (new commit),
    // and packed-refs (after gc). `--git-path` resolves these inside worktrees too. Only files
    // that exist are watched: Cargo takes a missing one as changed on every build, which
    // rebuilt the crate each time in a repository without packed-refs. When gc packs the
    // branch's ref, its loose file disappears (a change), and the next build watches
    // packed-refs instead.
    let mut watch = vec!["HEAD".to_string(), "packed-refs".to_string()];
    watch.extend(git(&["symbolic-ref", "-q", "HEAD"]));
    for p in watch {
        if let Some(path) = git(&["rev-parse", "--git-path", &p]) {
            if std::path::Path::new(&path).exists() {
                println!("cargo:rerun-if-changed={path}");
            }
        }
    }
    println!("cargo:rustc-env=PUSHPACK_GIT_COMMIT={commit}");
}
