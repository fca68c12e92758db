//! Hostile cases of `hydroid export fmu` besides where it writes (tests/hostile/exports.rs):
//! the FMU library as a device, a pipe, a folder, a program, a library without the FMI
//! functions, a truncated, foreign or huge file; absurd `--max-step` values; folders that are
//! not (or no longer) what a run wrote, and where the start values come from. docs/fmu.md
//! says what is refused and why.

use super::exports::{export, mkfifo, run_as, spheroid, spheroid_and_fmu, LIB, STATES};
use super::{refused, run_table, warned, Case, Expect};
use hydroid::app::export::fmu::library::{self, stand_in, stand_in_fmi};
use object::elf;
use std::path::Path;

/// The system's C library, if it is where Linux distributions put it.
fn libc() -> Option<&'static str> {
    [
        "/lib/x86_64-linux-gnu/libc.so.6",
        "/usr/lib/x86_64-linux-gnu/libc.so.6",
        "/lib64/libc.so.6",
        "/usr/lib64/libc.so.6",
        "/usr/lib/libc.so.6",
    ]
    .into_iter()
    .find(|p| Path::new(p).is_file())
}

/// The FMU library as cargo built it: beside the test's hydroid (`cargo build`) or in its
/// deps/ folder (`cargo test`, for fmu/tests/ffi.rs), if the fmu member was built.
fn built_library() -> Option<std::path::PathBuf> {
    let bin = Path::new(env!("CARGO_BIN_EXE_hydroid"));
    let name = "libhydroid_fmu.so";
    [
        bin.with_file_name(name),
        bin.with_file_name("deps").join(name),
    ]
    .into_iter()
    .find(|p| p.is_file())
}

/// `export fmu out/s -o v.fmu --library LIBRARY`, refused with `words`.
fn lib(name: &str, library: &str, words: &[&str]) -> Case {
    Case::new(
        name,
        &format!("export fmu out/s -o v.fmu --library {library}"),
        refused(words),
    )
    .setup(spheroid)
}

/// [`lib`] of a library written by the set-up with `bytes`.
fn written(name: &str, bytes: Vec<u8>, words: &[&str]) -> Case {
    lib(name, "written.so", words).setup(move |d| {
        spheroid(d);
        std::fs::write(d.join("written.so"), &bytes).unwrap();
    })
}

#[test]
fn the_library_is_a_regular_file_of_bounded_size() {
    let cases = vec![
        lib("/dev/zero", "/dev/zero", &["/dev/zero", "character device"]),
        lib("/dev/null", "/dev/null", &["/dev/null", "character device"]),
        lib("a folder", "cfd_exports", &["cfd_exports", "directory"]),
        lib(
            "a missing file",
            "none.so",
            &["none.so", "does not exist", "cargo build"],
        ),
        written("an empty file", Vec::new(), &["written.so", "empty"]),
        Case::new(
            "a named pipe",
            "export fmu out/s -o v.fmu --library lib.fifo",
            refused(&["lib.fifo", "named pipe"]),
        )
        .setup(|d| {
            spheroid(d);
            mkfifo(&d.join("lib.fifo"));
        }),
        Case::new(
            "a link to /dev/zero",
            "export fmu out/s -o v.fmu --library zero.so",
            refused(&["zero.so", "character device"]),
        )
        .setup(|d| {
            spheroid(d);
            std::os::unix::fs::symlink("/dev/zero", d.join("zero.so")).unwrap();
        }),
        Case::new(
            "a dangling link",
            "export fmu out/s -o v.fmu --library gone.so",
            refused(&["gone.so", "dangling"]),
        )
        .setup(|d| {
            spheroid(d);
            std::os::unix::fs::symlink(d.join("nowhere.so"), d.join("gone.so")).unwrap();
        }),
        // refused from its size: a read of it would take minutes and 600 MB
        Case::new(
            "a huge sparse file",
            "export fmu out/s -o v.fmu --library huge.so",
            refused(&["huge.so", "larger than the 512 MiB"]),
        )
        .setup(|d| {
            spheroid(d);
            let f = std::fs::File::create(d.join("huge.so")).unwrap();
            f.set_len(library::MAX_LIBRARY_BYTES + 1).unwrap();
        }),
    ];
    run_table("fmu (the library's file)", cases);
}

/// /bin/ls, the C library and the FMU library cargo built, where they are (a note says which
/// case is skipped).
fn system_libraries() -> Vec<Case> {
    let mut cases = Vec::new();
    if Path::new("/bin/ls").is_file() {
        cases.push(lib("/bin/ls", "/bin/ls", &["/bin/ls", "executable", "FMI"]));
    }
    match libc() {
        Some(c) => cases.push(lib(
            "the C library",
            c,
            &[
                "libc.so.6",
                "defines none of the 34 FMI 2.0 co-simulation functions",
            ],
        )),
        None => eprintln!("hostile::fmu: no libc.so.6 in the usual places; case skipped"),
    }
    match built_library() {
        Some(p) => cases.push(
            Case::new(
                "the built library",
                &format!("export fmu out/s -o v.fmu --library {}", p.display()),
                Expect::Fine,
            )
            .setup(spheroid),
        ),
        None => eprintln!(
            "hostile::fmu: no libhydroid_fmu.so beside the test's hydroid (the fmu member was \
             not built); case skipped"
        ),
    }
    cases
}

#[test]
fn the_library_is_an_x86_64_shared_object_with_the_fmi_functions() {
    let all = library::FMI2_CO_SIMULATION_FUNCTIONS;
    let x86 = elf::EM_X86_64;
    let mut truncated = stand_in_fmi();
    truncated.truncate(200);
    let mut narrow = stand_in_fmi();
    narrow[library::EI_CLASS] = 1;
    let no_step: Vec<&str> = all.iter().copied().filter(|f| *f != "fmi2DoStep").collect();
    let mut cases = vec![
        lib("a text file", "configs/spheroid.toml", &["not an ELF file"]),
        lib(
            "a CSV export",
            "cfd_exports/surge_run.csv",
            &["not an ELF file"],
        ),
        written(
            "a truncated ELF",
            truncated,
            &["written.so", "truncated or damaged"],
        ),
        written("a 32-bit ELF", narrow, &["32-bit"]),
        written(
            "a library for another processor",
            stand_in(elf::ET_DYN, elf::EM_AARCH64, all, None),
            &["another processor"],
        ),
        written(
            "an executable",
            stand_in(elf::ET_EXEC, x86, all, None),
            &["executable", "not a shared library"],
        ),
        written(
            "a position-independent executable",
            stand_in(elf::ET_DYN, x86, &["main"], Some(elf::DF_1_PIE)),
            &["position-independent executable", "FMI"],
        ),
        written(
            "an object file",
            stand_in(elf::ET_REL, x86, all, None),
            &["object file"],
        ),
        written(
            "a library without the FMI functions",
            stand_in(elf::ET_DYN, x86, &["malloc"], None),
            &[
                "defines none of the 34 FMI 2.0 co-simulation functions",
                "fmi2Instantiate",
            ],
        ),
        written(
            "a library lacking fmi2DoStep",
            stand_in(elf::ET_DYN, x86, &no_step, None),
            &["lacks 1 of the FMI 2.0 co-simulation functions: fmi2DoStep"],
        ),
        Case::new(
            "an FMU as the library",
            "export fmu out/s -o w.fmu --library v.fmu",
            refused(&["v.fmu", "not an ELF file"]),
        )
        .setup(|d| spheroid_and_fmu(d, "v.fmu")),
        Case::new(
            "the stand-in library",
            "export fmu out/s -o v.fmu --library lib.so",
            Expect::Fine,
        )
        .setup(spheroid),
    ];
    cases.extend(system_libraries());
    run_table("fmu (the library's contents)", cases);
}

#[test]
fn absurd_steps_are_refused() {
    let step = |value: &str, expect: Expect| {
        Case::new(
            &format!("--max-step {value}"),
            &export("s", "v.fmu", &format!("--max-step {value}")),
            expect,
        )
        .setup(spheroid)
    };
    let bounds = || refused(&["--max-step", "1e-5 s", "communication step"]);
    let mut cases: Vec<Case> = [
        "0", "-0", "-1", "nan", "NaN", "inf", "-inf", "1e-300", "1e300",
    ]
    .into_iter()
    .chain(["9e-6", "1.5", "-1e-3"])
    .map(|v| step(v, bounds()))
    .collect();
    cases.push(step("abc", refused(&["--max-step", "invalid value"])));
    cases.push(step("1e-5", Expect::Fine));
    cases.push(step("1", Expect::Fine));
    run_table("fmu (--max-step)", cases);
}

/// `export fmu OUTDIR -o v.fmu`, refused with `words`.
fn folder(name: &str, outdir: &str, words: &[&str]) -> Case {
    Case::new(
        name,
        &format!("export fmu {outdir} -o v.fmu --library {LIB}"),
        refused(words),
    )
    .setup(spheroid)
}

/// The spheroid run with `file` of its output edited.
fn edited(file: &'static str) -> Case {
    Case::new(
        &format!("edited {file}"),
        &export("s", "v.fmu", "--force"),
        refused(&["out/s", file, "edited since hydroid wrote it"]),
    )
    .setup(move |d| {
        spheroid(d);
        let p = d.join("out/s").join(file);
        let mut text = std::fs::read(&p).unwrap();
        text.extend_from_slice(b"\n ");
        std::fs::write(p, text).unwrap();
    })
}

/// Removes the output's marker (an output of an earlier hydroid).
fn unmark(d: &Path) {
    std::fs::remove_file(d.join("out/s/.hydroid-output.json")).unwrap();
}

#[test]
fn only_an_unedited_output_of_a_run_is_exported() {
    let cases = vec![
        folder(
            "the exports folder",
            "cfd_exports",
            &["cfd_exports", "no results.json"],
        ),
        folder("the configs folder", "configs", &["no results.json"]),
        folder(
            "a missing folder",
            "out/nope",
            &["out/nope", "no results.json"],
        ),
        folder("a file", "configs/spheroid.toml", &["no results.json"]),
        folder("/dev/null", "/dev/null", &["no results.json"]),
        edited("results.json"),
        edited("config.toml"),
        edited("inputs.json"),
        edited("rerun.json"),
        edited(STATES),
        Case::new(
            "garbled results without a marker",
            &export("s", "v.fmu", ""),
            refused(&["results.json", "not a hydroid results file"]),
        )
        .setup(|d| {
            spheroid(d);
            unmark(d);
            std::fs::write(d.join("out/s/results.json"), "{").unwrap();
        }),
        Case::new(
            "garbled rerun.json without a marker",
            &export("s", "v.fmu", ""),
            refused(&["rerun.json", "not a hydroid file"]),
        )
        .setup(|d| {
            spheroid(d);
            unmark(d);
            std::fs::write(d.join("out/s/rerun.json"), "[]").unwrap();
        }),
        // an output of an earlier hydroid (no marker) is exported as it is
        Case::new(
            "an output without a marker",
            &export("s", "v.fmu", ""),
            Expect::Fine,
        )
        .setup(|d| {
            spheroid(d);
            unmark(d);
        }),
    ];
    run_table("fmu (output folders)", cases);
}

#[test]
fn the_model_needs_an_hekf_stage_and_its_start_values_are_named() {
    let cases = vec![
        Case::new(
            "a run without HEKF",
            &export("p", "v.fmu", ""),
            refused(&["results.json", "no HEKF stage", "[hekf]"]),
        )
        .setup(|d| {
            run_as(
                d,
                "configs/spheroid.toml",
                &["--set", "hekf.enabled=false"],
                "p",
            )
        }),
        Case::new(
            "the smoother off: filtered start values",
            &export("f", "v.fmu", ""),
            warned(&["start values: the filtered states", "smoother was off"]),
        )
        .setup(|d| {
            run_as(
                d,
                "configs/spheroid.toml",
                &["--set", "hekf.smoother=false"],
                "f",
            )
        }),
        Case::new(
            "the smoother on: smoothed start values",
            &export("s", "v.fmu", ""),
            warned(&["start values: the smoothed states", STATES]),
        )
        .setup(spheroid),
        Case::new(
            "no state series: zero start values",
            &export("s", "v.fmu", ""),
            warned(&["start values: zero"]),
        )
        .setup(|d| {
            spheroid(d);
            unmark(d);
            std::fs::remove_file(d.join("out/s").join(STATES)).unwrap();
        }),
    ];
    run_table("fmu (models and start values)", cases);
}
