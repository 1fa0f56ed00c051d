//! `strata` as a shell runs it: piped into a reader that stops early.

/// `strata info ... | head` stops strata as it stops `cat`, by SIGPIPE, not with a
/// panic and a backtrace on standard error.
#[cfg(unix)]
#[test]
fn a_closed_output_pipe_ends_strata_quietly() {
    use std::os::unix::process::ExitStatusExt;
    use std::process::{Command, Stdio};

    let (reader, writer) = std::io::pipe().expect("a pipe");
    // Nobody reads: the first line strata prints meets a closed pipe.
    drop(reader);
    let sample = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("data/sample.grdecl");
    let out = Command::new(env!("CARGO_BIN_EXE_strata"))
        .arg("info")
        .arg(&sample)
        .stdout(writer)
        .stderr(Stdio::piped())
        .output()
        .expect("the strata binary runs");
    let said = String::from_utf8_lossy(&out.stderr);
    assert_eq!(
        out.status.signal(),
        Some(libc::SIGPIPE),
        "{:?}: {said}",
        out.status
    );
    assert!(said.is_empty(), "{said}");
}
