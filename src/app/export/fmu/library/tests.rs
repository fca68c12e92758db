use super::*;

#[test]
fn a_shared_library_with_the_fmi_functions_passes() {
    let lib = stand_in_fmi();
    check(&lib).unwrap();
    let names = defined_functions(&lib).unwrap();
    assert_eq!(names.len(), FMI2_CO_SIMULATION_FUNCTIONS.len());
    // the same bytes at an odd address (a buffer needs no alignment)
    let mut shifted = vec![0u8];
    shifted.extend_from_slice(&lib);
    check(&shifted[1..]).unwrap();
}

#[test]
fn what_is_not_the_library_is_named() {
    let all = FMI2_CO_SIMULATION_FUNCTIONS;
    let cases: Vec<(Vec<u8>, &str)> = vec![
        (Vec::new(), "empty"),
        (b"model = 1\n".to_vec(), "not an ELF file"),
        (b"\x7fELF".to_vec(), "truncated or damaged ELF header"),
        (stand_in(elf::ET_EXEC, elf::EM_X86_64, all, None), "ET_EXEC"),
        (
            stand_in(elf::ET_REL, elf::EM_X86_64, all, None),
            "object file",
        ),
        (
            stand_in(elf::ET_DYN, elf::EM_AARCH64, all, None),
            "another processor",
        ),
        (
            stand_in(elf::ET_DYN, elf::EM_X86_64, &["main"], Some(elf::DF_1_PIE)),
            "position-independent executable",
        ),
        (
            stand_in(elf::ET_DYN, elf::EM_X86_64, &["malloc", "printf"], None),
            "defines none of the 34 FMI 2.0 co-simulation functions",
        ),
        (
            stand_in(elf::ET_DYN, elf::EM_X86_64, &all[..32], None),
            "lacks 2 of the FMI 2.0 co-simulation functions: fmi2GetBooleanStatus, \
             fmi2GetStringStatus",
        ),
    ];
    for (bytes, want) in cases {
        let e = check(&bytes).unwrap_err();
        assert!(e.contains(want), "{want}: {e}");
    }
    let mut big_endian = stand_in_fmi();
    big_endian[EI_DATA] = elf::ELFDATA2MSB;
    assert!(check(&big_endian).unwrap_err().contains("big-endian"));
    let mut narrow = stand_in_fmi();
    narrow[EI_CLASS] = elf::ELFCLASS32;
    assert!(check(&narrow).unwrap_err().contains("32-bit"));
}

/// Every truncation and every single corrupted byte of a valid library is an error or a
/// pass, never a panic (the reads are bounds-checked).
#[test]
fn truncated_or_garbled_libraries_never_panic() {
    let lib = stand_in_fmi();
    for n in 0..lib.len() {
        let e = check(&lib[..n]).unwrap_err();
        assert!(!e.is_empty());
    }
    for k in 0..lib.len() {
        for value in [0x00, 0xff, 0x7f, 0x80] {
            let mut bad = lib.clone();
            bad[k] = value;
            let _ = check(&bad);
        }
    }
}

#[test]
fn only_regular_files_within_the_bound_are_read() {
    let dir = tempfile::tempdir().unwrap();
    let lib = dir.path().join("lib.so");
    std::fs::write(&lib, stand_in_fmi()).unwrap();
    assert_eq!(read(&lib).unwrap(), stand_in_fmi());
    let e = read(dir.path()).unwrap_err().to_string();
    assert!(
        e.contains("directory") && e.contains("libhydroid_fmu.so"),
        "{e}"
    );
    let e = read(&dir.path().join("none.so")).unwrap_err().to_string();
    assert!(e.contains("does not exist"), "{e}");
    // a sparse file over the bound is refused from its size, without reading it
    let huge = dir.path().join("huge.so");
    let f = std::fs::File::create(&huge).unwrap();
    f.set_len(MAX_LIBRARY_BYTES + 1).unwrap();
    let e = read(&huge).unwrap_err().to_string();
    assert!(e.contains("larger than the 512 MiB"), "{e}");
    #[cfg(unix)]
    {
        let e = read(Path::new("/dev/zero")).unwrap_err().to_string();
        assert!(e.contains("character device"), "{e}");
    }
}
