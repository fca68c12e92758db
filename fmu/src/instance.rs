//! One FMU instance in Rust terms: the model read from resources/model.json, its inputs,
//! initial-state parameters, state and time, and the FMI 2.0 co-simulation state machine
//! (FMI 2.0.x standard, section 4.2.4). Nothing here knows C; every error is a message.

use hydroid::app::export::fmu::description::guid;
use hydroid::app::export::fmu::spec::FmuSpec;
use std::path::{Path, PathBuf};

/// Where an instance is in its life (FMI 2.0 section 4.2.4, the co-simulation state machine).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    /// After fmi2Instantiate or fmi2Reset.
    Instantiated,
    /// Between fmi2EnterInitializationMode and fmi2ExitInitializationMode.
    Initialization,
    /// Stepping (slave initialized).
    Stepping,
    /// After fmi2Terminate.
    Terminated,
    /// A step failed: only fmi2Reset, fmi2Terminate, getters and fmi2FreeInstance are left.
    Failed,
}

/// Which variable a value reference names: inputs first, then the outputs (states), then
/// the initial-state parameters, as modelDescription.xml numbers them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Var {
    /// Input i.
    Input(usize),
    /// Output (state) i.
    Output(usize),
    /// Initial value of state i.
    Start(usize),
}

/// An instance.
#[derive(Debug)]
pub struct Instance {
    /// The model.
    pub spec: FmuSpec,
    /// Inputs, held over the next communication step.
    pub u: Vec<f64>,
    /// Initial-state parameters.
    pub starts: Vec<f64>,
    /// The state.
    pub x: Vec<f64>,
    /// The time of the state, s.
    pub time: f64,
    /// Where the instance is.
    pub phase: Phase,
}

/// The folder a `file:` URI names (RFC 8089: `file:///path`, `file://localhost/path` or
/// `file:/path`), percent-decoded (RFC 3986 section 2.1).
pub fn uri_to_path(uri: &str) -> Result<PathBuf, String> {
    let rest = uri
        .strip_prefix("file:")
        .ok_or_else(|| format!("resource location '{uri}' is not a file: URI"))?;
    let path = match rest.strip_prefix("//") {
        Some(authority_and_path) => {
            let slash = authority_and_path
                .find('/')
                .unwrap_or(authority_and_path.len());
            let host = &authority_and_path[..slash];
            if !(host.is_empty() || host.eq_ignore_ascii_case("localhost")) {
                return Err(format!(
                    "resource location '{uri}' names the host '{host}': only local files are read"
                ));
            }
            &authority_and_path[slash..]
        }
        None => rest,
    };
    let mut bytes = Vec::with_capacity(path.len());
    let raw = path.as_bytes();
    let mut i = 0;
    while i < raw.len() {
        if raw[i] == b'%' {
            let hex = raw
                .get(i + 1..i + 3)
                .and_then(|h| std::str::from_utf8(h).ok())
                .and_then(|h| u8::from_str_radix(h, 16).ok())
                .ok_or_else(|| format!("resource location '{uri}': bad percent escape"))?;
            bytes.push(hex);
            i += 3;
        } else {
            bytes.push(raw[i]);
            i += 1;
        }
    }
    use std::os::unix::ffi::OsStringExt;
    Ok(PathBuf::from(std::ffi::OsString::from_vec(bytes)))
}

impl Instance {
    /// Reads `resources/model.json` from `resources`, checks that its content gives `guid`
    /// (the FMU's modelDescription.xml and resources belong together) and that this
    /// library's model matches it.
    pub fn new(resources: &Path, expected_guid: &str) -> Result<Instance, String> {
        let path = resources.join("model.json");
        let bytes =
            std::fs::read(&path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
        let have = guid(&bytes);
        if have != expected_guid {
            return Err(format!(
                "{} gives the GUID {have}, but the importer asks for {expected_guid}: the \
                 resources are not those of this FMU's modelDescription.xml",
                path.display()
            ));
        }
        let text =
            String::from_utf8(bytes).map_err(|_| format!("{}: not UTF-8 text", path.display()))?;
        let what = path.display().to_string();
        let spec = FmuSpec::from_json(&text, &what).map_err(|e| e.to_string())?;
        spec.check().map_err(|e| format!("{what}: {e}"))?;
        let mut inst = Instance {
            u: Vec::new(),
            starts: Vec::new(),
            x: Vec::new(),
            time: 0.0,
            phase: Phase::Instantiated,
            spec,
        };
        inst.reset();
        Ok(inst)
    }

    /// Back to the state after instantiation: start values, time 0.
    pub fn reset(&mut self) {
        self.u = self.spec.inputs.iter().map(|v| v.start).collect();
        self.starts = self.spec.states.iter().map(|v| v.start).collect();
        self.x = self.starts.clone();
        self.time = 0.0;
        self.phase = Phase::Instantiated;
    }

    /// The variable of a value reference.
    pub fn var(&self, vr: u32) -> Result<Var, String> {
        let (ni, nx) = (self.spec.inputs.len(), self.spec.states.len());
        let i = vr as usize;
        if i < ni {
            Ok(Var::Input(i))
        } else if i < ni + nx {
            Ok(Var::Output(i - ni))
        } else if i < ni + 2 * nx {
            Ok(Var::Start(i - ni - nx))
        } else {
            Err(format!(
                "no Real variable has the value reference {vr} (0 to {})",
                ni + 2 * nx - 1
            ))
        }
    }

    /// The value of a variable.
    pub fn get(&self, vr: u32) -> Result<f64, String> {
        Ok(match self.var(vr)? {
            Var::Input(i) => self.u[i],
            Var::Output(i) => self.x[i],
            Var::Start(i) => self.starts[i],
        })
    }

    /// Sets a variable: an input at any time before fmi2Terminate, an initial-state
    /// parameter before fmi2ExitInitializationMode (variability "fixed"), an output never.
    pub fn set(&mut self, vr: u32, value: f64) -> Result<(), String> {
        if !value.is_finite() {
            return Err(format!(
                "value reference {vr}: {value} is not a finite number"
            ));
        }
        match self.var(vr)? {
            Var::Input(i) => match self.phase {
                Phase::Terminated | Phase::Failed => {
                    Err("inputs cannot be set after fmi2Terminate or a failed step".into())
                }
                _ => {
                    self.u[i] = value;
                    Ok(())
                }
            },
            Var::Start(i) => match self.phase {
                Phase::Instantiated | Phase::Initialization => {
                    self.starts[i] = value;
                    self.x[i] = value;
                    Ok(())
                }
                _ => Err(format!(
                    "{} is a fixed parameter: set it before fmi2ExitInitializationMode",
                    hydroid::app::export::fmu::description::start_parameter(
                        &self.spec.states[i].name
                    )
                )),
            },
            Var::Output(i) => Err(format!(
                "{} is an output (a state): set its initial value {} instead",
                self.spec.states[i].name,
                hydroid::app::export::fmu::description::start_parameter(&self.spec.states[i].name)
            )),
        }
    }

    /// fmi2DoStep: integrates from `t` to `t + h` with the inputs held.
    pub fn do_step(&mut self, t: f64, h: f64) -> Result<(), String> {
        if self.phase != Phase::Stepping {
            return Err(format!(
                "fmi2DoStep in the {:?} phase: call fmi2ExitInitializationMode first (and not \
                 after fmi2Terminate or a failed step)",
                self.phase
            ));
        }
        if !(h.is_finite() && h > 0.0) {
            return Err(format!("communication step size {h} is not positive"));
        }
        if !t.is_finite() || (t - self.time).abs() > 1e-9 * self.time.abs().max(1.0) {
            return Err(format!(
                "the communication point {t} s is not the instance's time {} s",
                self.time
            ));
        }
        match self.spec.advance(&self.x, &self.u, t, h) {
            Ok(x) => {
                self.x = x;
                self.time = t + h;
                Ok(())
            }
            Err(e) => {
                self.phase = Phase::Failed;
                Err(e.to_string())
            }
        }
    }
}
