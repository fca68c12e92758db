//! The FMU's shared library (binaries/linux64/IDENTIFIER.so): read as a regular file within a
//! size bound (a pipe or a device is refused before it is opened, a huge file from its size),
//! and checked as what an importer loads on Linux x86-64: a 64-bit little-endian ELF shared
//! object (ET_DYN, EM_X86_64; not a position-independent program) whose dynamic symbol table
//! defines every function of the FMI 2.0 co-simulation API (FMI 2.0.x, sections 2.1 and 4.2)
//! that hydroid's library (the workspace member fmu/) exports. The ELF structures are read
//! with the `object` crate, whose reads are bounds-checked: a truncated or garbled file is an
//! error, never a panic.

use crate::base::error::{Error, Result};
use crate::io::formats::input::{check_regular, format_size, stream, Limits};
use object::elf;
use object::read::elf::{Dyn, FileHeader, Sym};
use object::LittleEndian as LE;
use std::path::Path;

/// The largest library read: 512 MiB. hydroid's is a few MB (tens in a debug build); a file
/// larger than this is not it.
pub const MAX_LIBRARY_BYTES: u64 = 512 << 20;

/// The FMI 2.0 functions an FMU for co-simulation exports (FMI 2.0.x: the common functions
/// of section 2.1 and the co-simulation functions of section 4.2), every one of which the
/// library of fmu/ defines (fmu/src/api.rs; `fmu/tests/ffi.rs` checks the two lists agree).
pub const FMI2_CO_SIMULATION_FUNCTIONS: &[&str] = &[
    "fmi2GetTypesPlatform",
    "fmi2GetVersion",
    "fmi2SetDebugLogging",
    "fmi2Instantiate",
    "fmi2FreeInstance",
    "fmi2SetupExperiment",
    "fmi2EnterInitializationMode",
    "fmi2ExitInitializationMode",
    "fmi2Terminate",
    "fmi2Reset",
    "fmi2GetReal",
    "fmi2GetInteger",
    "fmi2GetBoolean",
    "fmi2GetString",
    "fmi2SetReal",
    "fmi2SetInteger",
    "fmi2SetBoolean",
    "fmi2SetString",
    "fmi2GetFMUstate",
    "fmi2SetFMUstate",
    "fmi2FreeFMUstate",
    "fmi2SerializedFMUstateSize",
    "fmi2SerializeFMUstate",
    "fmi2DeSerializeFMUstate",
    "fmi2GetDirectionalDerivative",
    "fmi2SetRealInputDerivatives",
    "fmi2GetRealOutputDerivatives",
    "fmi2DoStep",
    "fmi2CancelStep",
    "fmi2GetStatus",
    "fmi2GetRealStatus",
    "fmi2GetIntegerStatus",
    "fmi2GetBooleanStatus",
    "fmi2GetStringStatus",
];

/// The index of the class (32 or 64-bit) in the ELF identification (e_ident[EI_CLASS]).
pub const EI_CLASS: usize = 4;
/// The index of the byte order in the ELF identification (e_ident[EI_DATA]).
pub const EI_DATA: usize = 5;

/// What the library must be, for messages.
const WANTED: &str = "the FMU's shared library, libhydroid_fmu.so (built by `cargo build \
                      --release` at the repository root, or `cargo build -p hydroid-fmu`)";

/// Reads the library at `path`: a regular file (symbolic links followed) of at most
/// [`MAX_LIBRARY_BYTES`], then [`check`]ed. Every refusal names the file and what it should be.
pub fn read(path: &Path) -> Result<Vec<u8>> {
    let refuse = |why: String| Error::Usage(format!("the FMU library {}: {why}", path.display()));
    let size = check_regular(path).map_err(|e| refuse(format!("{}; give {WANTED}", e.message)))?;
    if size > MAX_LIBRARY_BYTES {
        return Err(refuse(format!(
            "the file is {}, larger than the {} hydroid reads as a library: it is not {WANTED}",
            format_size(size),
            format_size(MAX_LIBRARY_BYTES)
        )));
    }
    let limits = Limits {
        max_bytes: MAX_LIBRARY_BYTES,
        ..Limits::default()
    };
    let mut bytes = Vec::with_capacity(size as usize);
    stream(path, &limits, |chunk| {
        bytes.extend_from_slice(chunk);
        Ok(())
    })
    .map_err(|e| refuse(e.message))?;
    check(&bytes).map_err(|why| refuse(format!("{why}; give {WANTED}")))?;
    Ok(bytes)
}

/// Checks that `bytes` are a Linux x86-64 shared library exporting every function of
/// [`FMI2_CO_SIMULATION_FUNCTIONS`]; the error says what the file is or what it lacks.
pub fn check(bytes: &[u8]) -> std::result::Result<(), String> {
    let symbols = defined_functions(bytes)?;
    let missing: Vec<&str> = FMI2_CO_SIMULATION_FUNCTIONS
        .iter()
        .copied()
        .filter(|f| !symbols.iter().any(|s| s == f))
        .collect();
    if missing.is_empty() {
        return Ok(());
    }
    let what = if missing.len() == FMI2_CO_SIMULATION_FUNCTIONS.len() {
        format!(
            "defines none of the {} FMI 2.0 co-simulation functions (fmi2Instantiate, \
             fmi2DoStep, fmi2GetVersion ...)",
            missing.len()
        )
    } else {
        format!(
            "lacks {} of the FMI 2.0 co-simulation functions: {}",
            missing.len(),
            missing.join(", ")
        )
    };
    Err(format!(
        "a shared library, but its dynamic symbol table ({} functions) {what}, which an \
         importer calls",
        symbols.len()
    ))
}

/// The names of the functions a 64-bit little-endian x86-64 ELF shared object defines in its
/// dynamic symbol table (what a loader can find in it), or what the file is instead.
pub fn defined_functions(bytes: &[u8]) -> std::result::Result<Vec<String>, String> {
    if !bytes.starts_with(b"\x7fELF") {
        return Err(if bytes.is_empty() {
            "the file is empty, not an ELF shared library".into()
        } else {
            "not an ELF file (no ELF header): not a Linux shared library".into()
        });
    }
    match (bytes.get(EI_CLASS), bytes.get(EI_DATA)) {
        (Some(&elf::ELFCLASS64), Some(&elf::ELFDATA2LSB)) => {}
        (Some(&elf::ELFCLASS32), _) => {
            return Err(
                "a 32-bit ELF file: the FMU's binaries/linux64 needs a 64-bit library".into(),
            )
        }
        (Some(&elf::ELFCLASS64), Some(&elf::ELFDATA2MSB)) => {
            return Err("a big-endian ELF file, not one for x86-64".into())
        }
        _ => return Err("a truncated or damaged ELF header".into()),
    }
    let garbled = |e: object::read::Error| format!("a truncated or damaged ELF file ({e})");
    let header = elf::FileHeader64::<LE>::parse(bytes).map_err(garbled)?;
    let endian = LE;
    let machine = header.e_machine(endian);
    if machine != elf::EM_X86_64 {
        return Err(format!(
            "an ELF file for another processor (e_machine {machine}, x86-64 is {}): the FMU's \
             binaries/linux64 needs an x86-64 library",
            elf::EM_X86_64
        ));
    }
    match header.e_type(endian) {
        elf::ET_DYN => {}
        elf::ET_EXEC => {
            return Err("an executable program (ELF type ET_EXEC), not a shared library".into())
        }
        elf::ET_REL => {
            return Err("an object file (ELF type ET_REL), not a linked shared library".into())
        }
        elf::ET_CORE => return Err("a core dump (ELF type ET_CORE), not a shared library".into()),
        t => {
            return Err(format!(
                "an ELF file of type {t}, not a shared library (ET_DYN)"
            ))
        }
    }
    let sections = header.sections(endian, bytes).map_err(garbled)?;
    if let Some((dynamic, _)) = sections.dynamic(endian, bytes).map_err(garbled)? {
        let pie = dynamic.iter().any(|d| {
            d.d_tag(endian) == elf::DT_FLAGS_1 && d.d_val(endian) & u64::from(elf::DF_1_PIE) != 0
        });
        if pie {
            return Err(
                "an executable program (a position-independent executable, DF_1_PIE), not a \
                 shared library; it exports none of the FMI 2.0 co-simulation functions"
                    .into(),
            );
        }
    }
    let table = sections
        .symbols(endian, bytes, elf::SHT_DYNSYM)
        .map_err(garbled)?;
    let mut names = Vec::new();
    for s in table.iter() {
        let function = matches!(s.st_type(), elf::STT_FUNC | elf::STT_GNU_IFUNC);
        let exported = matches!(s.st_bind(), elf::STB_GLOBAL | elf::STB_WEAK);
        if function && exported && !s.is_undefined(endian) {
            let name = s.name(endian, table.strings()).map_err(garbled)?;
            names.push(String::from_utf8_lossy(name).into_owned());
        }
    }
    Ok(names)
}

/// The stand-in library of the tests: every function of [`FMI2_CO_SIMULATION_FUNCTIONS`] in
/// a [`stand_in`] shared object for x86-64.
pub fn stand_in_fmi() -> Vec<u8> {
    stand_in(
        elf::ET_DYN,
        elf::EM_X86_64,
        FMI2_CO_SIMULATION_FUNCTIONS,
        None,
    )
}

/// A minimal ELF64 little-endian file written from the ELF specification (System V ABI,
/// "Object Files": the file header, section headers, .dynstr, .dynsym and .dynamic): of type
/// `e_type` for `machine`, its dynamic symbol table defining `functions` (global functions),
/// and DT_FLAGS_1 = `flags_1` in .dynamic when given. Not loadable (no program headers), but
/// all [`check`] reads: a stand-in library for tests (of this crate, and of the command line,
/// whose test binary cannot count on the FMU member having been built).
pub fn stand_in(e_type: u16, machine: u16, functions: &[&str], flags_1: Option<u32>) -> Vec<u8> {
    let mut dynstr = vec![0u8];
    let mut dynsym = vec![0u8; 24]; // the null symbol
    for f in functions {
        let name = dynstr.len() as u32;
        dynstr.extend_from_slice(f.as_bytes());
        dynstr.push(0);
        dynsym.extend_from_slice(&name.to_le_bytes());
        dynsym.push((elf::STB_GLOBAL << 4) | elf::STT_FUNC); // st_info
        dynsym.push(0); // st_other
        dynsym.extend_from_slice(&5u16.to_le_bytes()); // st_shndx: a section, not SHN_UNDEF
        dynsym.extend_from_slice(&0x1000u64.to_le_bytes()); // st_value
        dynsym.extend_from_slice(&16u64.to_le_bytes()); // st_size
    }
    let mut dynamic = Vec::new();
    if let Some(f) = flags_1 {
        dynamic.extend_from_slice(&elf::DT_FLAGS_1.to_le_bytes());
        dynamic.extend_from_slice(&u64::from(f).to_le_bytes());
    }
    dynamic.extend_from_slice(&[0u8; 16]); // DT_NULL
    let shstrtab = b"\0.dynstr\0.dynsym\0.dynamic\0.shstrtab\0".to_vec();
    // sections after the 64-byte header, each at an 8-byte boundary
    let mut body: Vec<u8> = Vec::new();
    let mut place = |data: &[u8]| {
        while !(64 + body.len()).is_multiple_of(8) {
            body.push(0);
        }
        let at = 64 + body.len() as u64;
        body.extend_from_slice(data);
        (at, data.len() as u64)
    };
    let s_dynstr = place(&dynstr);
    let s_dynsym = place(&dynsym);
    let s_dynamic = place(&dynamic);
    let s_shstr = place(&shstrtab);
    while !body.len().is_multiple_of(8) {
        body.push(0);
    }
    let shoff = 64 + body.len() as u64;
    // (name offset in .shstrtab, type, (offset, size), link, info, entsize)
    let headers = [
        (0u32, 0u32, (0u64, 0u64), 0u32, 0u32, 0u64),
        (1, elf::SHT_STRTAB, s_dynstr, 0, 0, 0),
        (9, elf::SHT_DYNSYM, s_dynsym, 1, 1, 24),
        (17, elf::SHT_DYNAMIC, s_dynamic, 1, 0, 16),
        (26, elf::SHT_STRTAB, s_shstr, 0, 0, 0),
    ];
    let mut out = Vec::new();
    out.extend_from_slice(b"\x7fELF");
    out.extend_from_slice(&[elf::ELFCLASS64, elf::ELFDATA2LSB, 1, 0]);
    out.extend_from_slice(&[0u8; 8]);
    out.extend_from_slice(&e_type.to_le_bytes());
    out.extend_from_slice(&machine.to_le_bytes());
    out.extend_from_slice(&1u32.to_le_bytes()); // e_version
    out.extend_from_slice(&0u64.to_le_bytes()); // e_entry
    out.extend_from_slice(&0u64.to_le_bytes()); // e_phoff
    out.extend_from_slice(&shoff.to_le_bytes());
    out.extend_from_slice(&0u32.to_le_bytes()); // e_flags
    for half in [64u16, 56, 0, 64, headers.len() as u16, 4] {
        // e_ehsize, e_phentsize, e_phnum, e_shentsize, e_shnum, e_shstrndx
        out.extend_from_slice(&half.to_le_bytes());
    }
    assert_eq!(out.len(), 64);
    out.extend_from_slice(&body);
    for (name, kind, (offset, size), link, info, entsize) in headers {
        out.extend_from_slice(&name.to_le_bytes());
        out.extend_from_slice(&kind.to_le_bytes());
        out.extend_from_slice(&0u64.to_le_bytes()); // sh_flags
        out.extend_from_slice(&0u64.to_le_bytes()); // sh_addr
        out.extend_from_slice(&offset.to_le_bytes());
        out.extend_from_slice(&size.to_le_bytes());
        out.extend_from_slice(&link.to_le_bytes());
        out.extend_from_slice(&info.to_le_bytes());
        out.extend_from_slice(&8u64.to_le_bytes()); // sh_addralign
        out.extend_from_slice(&entsize.to_le_bytes());
    }
    out
}

#[cfg(test)]
mod tests;
