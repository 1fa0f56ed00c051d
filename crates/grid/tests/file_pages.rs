//! Reading a large array from a mapped Eclipse binary file gives its file pages back
//! as it decodes them: the array is not resident twice. Alone in its test binary, so
//! that no other test's files change the process's resident file pages meanwhile.

use strata_grid::eclbin::{EclFile, RecordWriter};

mod common;

/// Resident file-backed memory of this process, in bytes: Linux's RssFile, and
/// RssShmem for a file on tmpfs.
#[cfg(target_os = "linux")]
fn resident_file_bytes() -> u64 {
    common::status_bytes("RssFile") + common::status_bytes("RssShmem")
}

#[cfg(target_os = "linux")]
#[test]
fn decoded_arrays_leave_their_file_pages_to_the_page_cache() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let path = dir.path().join("BIG.INIT");
    // 40 M values, 160 MB: several pieces of decoding, each given back in turn.
    let values: Vec<f32> = (0..40_000_000u32)
        .map(|n| (n % 9973) as f32 * 0.25)
        .collect();
    let mut writer = RecordWriter::create(&path).expect("the file is created");
    writer.real("PORO", &values).expect("PORO is written");
    writer.inte("AFTER", &[7, 8, 9]).expect("AFTER is written");
    writer.finish().expect("the file is written");

    let file = EclFile::open(&path).expect("the file maps");
    let mapped = resident_file_bytes();
    let mut records = file.records();
    let poro = records
        .next()
        .expect("a first keyword")
        .expect("PORO reads");
    let decoded = poro.to_f32().expect("PORO decodes");
    let after_decoding = resident_file_bytes();
    assert!(decoded == values, "PORO decodes to what was written");
    assert!(
        mapped >= 150_000_000 && after_decoding + 140_000_000 <= mapped,
        "resident file pages: {mapped} bytes mapped, {after_decoding} after decoding"
    );
    // What was given back reads again from the file, unchanged; so does the rest.
    assert!(poro.to_f32().expect("PORO decodes again") == values);
    let after = records
        .next()
        .expect("a second keyword")
        .expect("AFTER reads");
    assert_eq!(after.to_i32().expect("AFTER decodes"), vec![7, 8, 9]);
    assert!(records.next().is_none());
}
