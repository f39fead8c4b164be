//! Scenes are data: TOML files under `host-sim/scenes/`, the same files built in by name.
//!
//! A scene declares the surface it needs; the run is then compiled for that surface only (a plane
//! scene never computes sphere geometry).

use serde::Deserialize;
use softfinger_core::contact::decompose::Method;
use softfinger_core::contact::ModelChoice;
use std::path::{Path, PathBuf};

/// The built-in scenes: (name, TOML text). The first is the default.
pub const BUILT_IN: [(&str, &str); 5] = [
    (
        "finger-on-plane",
        include_str!("../../host-sim/scenes/finger-on-plane.toml"),
    ),
    (
        "finger-on-sphere",
        include_str!("../../host-sim/scenes/finger-on-sphere.toml"),
    ),
    (
        "finger-in-bowl",
        include_str!("../../host-sim/scenes/finger-in-bowl.toml"),
    ),
    (
        "finger-on-cylinder",
        include_str!("../../host-sim/scenes/finger-on-cylinder.toml"),
    ),
    (
        "finger-slide-twist",
        include_str!("../../host-sim/scenes/finger-slide-twist.toml"),
    ),
];

/// The object surface a scene declares.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase", deny_unknown_fields)]
pub enum SurfaceSpec {
    /// A horizontal plane.
    Plane,
    /// A fixed sphere of radius `radius_m` (m), the fingertip on top of it.
    Sphere { radius_m: f64 },
    /// A concave spherical bowl of inner radius `radius_m` (m, larger than the fingertip's), the
    /// fingertip inside it, first touching its bottom.
    Bowl { radius_m: f64 },
    /// A fixed cylinder of radius `radius_m` (m), its axis along the base x axis, the fingertip
    /// first touching its top.
    Cylinder { radius_m: f64 },
}

impl SurfaceSpec {
    /// The radius of a curved surface; `None` for the plane.
    pub fn radius_m(&self) -> Option<f64> {
        match *self {
            SurfaceSpec::Plane => None,
            SurfaceSpec::Sphere { radius_m }
            | SurfaceSpec::Bowl { radius_m }
            | SurfaceSpec::Cylinder { radius_m } => Some(radius_m),
        }
    }

    /// The `kind` key of the scene file.
    pub fn kind(&self) -> &'static str {
        match self {
            SurfaceSpec::Plane => "plane",
            SurfaceSpec::Sphere { .. } => "sphere",
            SurfaceSpec::Bowl { .. } => "bowl",
            SurfaceSpec::Cylinder { .. } => "cylinder",
        }
    }
}

/// Changes to the hand script (see `plant::TouchScript`); absent fields keep its defaults.
#[derive(Clone, Copy, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScriptSpec {
    pub press_depth_m: Option<f64>,
    pub roll_rad: Option<f64>,
    pub twist_rad: Option<f64>,
    pub slide_m: Option<f64>,
    pub clearance_m: Option<f64>,
    /// Direction of the roll and the slide in the base xy plane, rad from +x towards +y.
    pub heading_rad: Option<f64>,
    /// Twist and slide at once (one phase) instead of one after the other.
    pub twist_while_sliding: Option<bool>,
}

/// Changes to the contact parameters; absent fields keep `ContactParams::DEFAULT`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSpec {
    pub fingertip_radius_m: Option<f32>,
    pub normal_stiffness: Option<f32>,
    pub normal_damping: Option<f32>,
    pub tangential_stiffness: Option<f32>,
    pub tangential_damping: Option<f32>,
    pub mu_s: Option<f32>,
    pub mu_k: Option<f32>,
    pub spin_stiffness: Option<f32>,
}

/// A scene file.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    pub name: String,
    #[serde(default)]
    pub description: String,
    #[serde(default = "default_method")]
    pub method: String,
    #[serde(default = "default_rate")]
    pub rate_hz: f64,
    #[serde(default = "default_duration")]
    pub duration_s: f64,
    /// The contact model the scene runs (`softfinger_core::contact::parts`): point-friction,
    /// rolling, spin, spin-rolling or full (absent: full). `host-sim model` tells which one a
    /// scene needs.
    #[serde(default)]
    pub model: Option<String>,
    pub surface: SurfaceSpec,
    #[serde(default)]
    pub script: ScriptSpec,
    #[serde(default)]
    pub contact: ContactSpec,
}

fn default_method() -> String {
    "exact".into()
}
fn default_rate() -> f64 {
    10_000.0
}
fn default_duration() -> f64 {
    4.3
}

/// Why a scene could not be loaded. Messages name the file (or built-in) and, for syntax, the line.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The TOML does not parse or does not match the scene's fields.
    #[error("{origin}{}: {message}", line.map(|l| format!(" line {l}")).unwrap_or_default())]
    Syntax {
        /// The file or built-in name.
        origin: String,
        /// 1-based line, when known.
        line: Option<usize>,
        /// The parser's message.
        message: String,
    },
    /// The scene parses but a value is out of range.
    #[error("{origin}: {problem}")]
    Invalid {
        /// The file or built-in name.
        origin: String,
        /// What is wrong.
        problem: SceneProblem,
    },
    /// Neither a built-in name nor an existing file.
    #[error(
        "no built-in scene or file named '{name}' (built-ins: {})",
        built_in_names()
    )]
    NotFound {
        /// The name or path asked for.
        name: String,
    },
    /// The file exists but cannot be read.
    #[error("{}: cannot read: {source}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// The operating system's reason.
        source: std::io::Error,
    },
}

/// A value of a parsed scene that is out of range.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SceneProblem {
    /// `method` names no decomposition method.
    #[error("unknown method '{0}' (exact, rpy, paper-verbatim)")]
    UnknownMethod(String),
    /// `model` names no contact model.
    #[error("unknown model '{0}' (point-friction, rolling, spin, spin-rolling, full)")]
    UnknownModel(String),
    /// `rate_hz` outside 1000..40000.
    #[error("rate_hz must be within 1000..40000, got {0}")]
    Rate(f64),
    /// `duration_s` outside (0, 3600].
    #[error("duration_s must be within (0, 3600], got {0}")]
    Duration(f64),
    /// `surface.radius_m` not positive.
    #[error("surface.radius_m must be positive, got {0}")]
    Radius(f64),
    /// `script.heading_rad` beyond ±2π.
    #[error("script.heading_rad must be within ±2π, got {0}")]
    Heading(f64),
}

fn built_in_names() -> String {
    BUILT_IN
        .iter()
        .map(|(n, _)| *n)
        .collect::<Vec<_>>()
        .join(", ")
}

impl Scene {
    /// Parse TOML text; `origin` names the source in errors (which carry the line).
    pub fn parse(text: &str, origin: &str) -> Result<Scene, SceneError> {
        let scene: Scene = toml::from_str(text).map_err(|e| {
            // An unknown key's span covers its whole table; point at the key's own line instead.
            let unknown_key_line = e
                .message()
                .strip_prefix("unknown field `")
                .and_then(|rest| rest.split('`').next())
                .and_then(|key| {
                    text.lines()
                        .position(|l| {
                            let l = l.trim_start();
                            l.starts_with(key) && l[key.len()..].trim_start().starts_with('=')
                        })
                        .map(|i| i + 1)
                });
            let line = unknown_key_line.or_else(|| {
                e.span()
                    .map(|s| text[..s.start.min(text.len())].lines().count().max(1))
            });
            SceneError::Syntax {
                origin: origin.to_string(),
                line,
                message: e.message().to_string(),
            }
        })?;
        scene.check().map_err(|problem| SceneError::Invalid {
            origin: origin.to_string(),
            problem,
        })?;
        Ok(scene)
    }

    /// A built-in scene by name, or a file path.
    pub fn load(name_or_path: &str) -> Result<Scene, SceneError> {
        if let Some((name, text)) = BUILT_IN.iter().find(|(n, _)| *n == name_or_path) {
            return Scene::parse(text, name);
        }
        let path = Path::new(name_or_path);
        if !path.exists() {
            return Err(SceneError::NotFound {
                name: name_or_path.to_string(),
            });
        }
        let text = std::fs::read_to_string(path).map_err(|source| SceneError::Read {
            path: path.to_path_buf(),
            source,
        })?;
        Scene::parse(&text, &path.display().to_string())
    }

    /// The default scene.
    pub fn default_scene() -> Scene {
        Scene::parse(BUILT_IN[0].1, BUILT_IN[0].0).expect("the built-in default scene parses")
    }

    /// The decomposition method.
    pub fn method(&self) -> Result<Method, SceneProblem> {
        Method::from_name(&self.method)
            .ok_or_else(|| SceneProblem::UnknownMethod(self.method.clone()))
    }

    /// The contact model the scene names (full when it names none).
    pub fn model(&self) -> Result<ModelChoice, SceneProblem> {
        match &self.model {
            None => Ok(ModelChoice::Full),
            Some(m) => {
                ModelChoice::from_name(m).ok_or_else(|| SceneProblem::UnknownModel(m.clone()))
            }
        }
    }

    /// The scene as TOML text (every field the command line can override, and the rest), for
    /// re-validation after overrides; [`Scene::parse`] of it gives the same scene.
    pub fn to_toml(&self) -> String {
        let mut surface = format!("kind = {:?}\n", self.surface.kind());
        if let Some(r) = self.surface.radius_m() {
            surface += &format!("radius_m = {r:?}\n");
        }
        let mut t = format!(
            "name = {:?}\ndescription = {:?}\nmethod = {:?}\nrate_hz = {:?}\nduration_s = {:?}\n[surface]\n{surface}",
            self.name, self.description, self.method, self.rate_hz, self.duration_s
        );
        if let Some(m) = &self.model {
            // Top-level keys must come before the first table.
            t = t.replacen("[surface]\n", &format!("model = {m:?}\n[surface]\n"), 1);
        }
        let sc = &self.script;
        t += "[script]\n";
        for (k, v) in [
            ("press_depth_m", sc.press_depth_m),
            ("roll_rad", sc.roll_rad),
            ("twist_rad", sc.twist_rad),
            ("slide_m", sc.slide_m),
            ("clearance_m", sc.clearance_m),
            ("heading_rad", sc.heading_rad),
        ] {
            if let Some(v) = v {
                t += &format!("{k} = {v:?}\n");
            }
        }
        if let Some(b) = sc.twist_while_sliding {
            t += &format!("twist_while_sliding = {b}\n");
        }
        let c = &self.contact;
        t += "[contact]\n";
        for (k, v) in [
            ("fingertip_radius_m", c.fingertip_radius_m),
            ("normal_stiffness", c.normal_stiffness),
            ("normal_damping", c.normal_damping),
            ("tangential_stiffness", c.tangential_stiffness),
            ("tangential_damping", c.tangential_damping),
            ("mu_s", c.mu_s),
            ("mu_k", c.mu_k),
            ("spin_stiffness", c.spin_stiffness),
        ] {
            if let Some(v) = v {
                t += &format!("{k} = {:?}\n", v as f64);
            }
        }
        t
    }

    fn check(&self) -> Result<(), SceneProblem> {
        self.method()?;
        self.model()?;
        if !(self.rate_hz.is_finite() && (1_000.0..=40_000.0).contains(&self.rate_hz)) {
            return Err(SceneProblem::Rate(self.rate_hz));
        }
        if !(self.duration_s.is_finite() && self.duration_s > 0.0 && self.duration_s <= 3600.0) {
            return Err(SceneProblem::Duration(self.duration_s));
        }
        if let Some(radius_m) = self.surface.radius_m() {
            if !(radius_m.is_finite() && radius_m > 0.0) {
                return Err(SceneProblem::Radius(radius_m));
            }
        }
        if let Some(h) = self.script.heading_rad {
            if !(h.is_finite() && h.abs() <= std::f64::consts::TAU) {
                return Err(SceneProblem::Heading(h));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The first built-in scene with its `model = "..."` line replaced by `line` (whatever
    /// model it names today).
    fn with_model_line(line: &str) -> String {
        let text = BUILT_IN[0].1;
        assert!(
            text.lines().any(|l| l.starts_with("model = ")),
            "the scene names a model"
        );
        text.lines()
            .map(|l| if l.starts_with("model = ") { line } else { l })
            .collect::<Vec<_>>()
            .join("\n")
    }

    #[test]
    fn a_scene_names_a_known_model_or_is_refused() {
        let s = Scene::parse(&with_model_line("model = \"spin-rolling\""), "x").unwrap();
        assert_eq!(s.model(), Ok(ModelChoice::SpinRolling));
        assert_eq!(Scene::parse(&s.to_toml(), "x").unwrap(), s);
        let s = Scene::parse(&with_model_line("model = \"full\""), "x").unwrap();
        assert_eq!(s.model(), Ok(ModelChoice::Full));
        let bad = with_model_line("model = \"fulll\"");
        let e = Scene::parse(&bad, "x").unwrap_err().to_string();
        assert!(e.contains("unknown model 'fulll'"), "{e}");
        let none = with_model_line("");
        assert_eq!(
            Scene::parse(&none, "x").unwrap().model(),
            Ok(ModelChoice::Full)
        );
    }

    #[test]
    fn built_ins_parse() {
        for (name, text) in BUILT_IN {
            let s = Scene::parse(text, name).unwrap();
            assert_eq!(s.name, name);
        }
        assert_eq!(Scene::default_scene().surface, SurfaceSpec::Plane);
        let kinds: Vec<&str> = BUILT_IN
            .iter()
            .map(|(n, t)| Scene::parse(t, n).unwrap().surface.kind())
            .collect();
        for k in ["plane", "sphere", "bowl", "cylinder"] {
            assert!(kinds.contains(&k), "no built-in {k} scene: {kinds:?}");
        }
    }

    #[test]
    fn curved_surfaces_need_a_positive_radius() {
        for kind in ["sphere", "bowl", "cylinder"] {
            let ok = format!("name = \"x\"\n[surface]\nkind = \"{kind}\"\nradius_m = 0.03\n");
            let s = Scene::parse(&ok, "ok.toml").unwrap();
            assert_eq!(s.surface.kind(), kind);
            assert_eq!(s.surface.radius_m(), Some(0.03));
            for bad in ["0.0", "-0.01", "nan"] {
                let t = format!("name = \"x\"\n[surface]\nkind = \"{kind}\"\nradius_m = {bad}\n");
                let e = Scene::parse(&t, "r.toml").unwrap_err().to_string();
                assert!(e.contains("radius_m"), "{kind} {bad}: {e}");
            }
            let missing = format!("name = \"x\"\n[surface]\nkind = \"{kind}\"\n");
            assert!(Scene::parse(&missing, "m.toml").is_err());
        }
        // The heading is bounded just above ±2π.
        let heading = |h: &str| {
            Scene::parse(
                &format!(
                    "name = \"x\"\n[surface]\nkind = \"plane\"\n[script]\nheading_rad = {h}\n"
                ),
                "h.toml",
            )
        };
        assert!(heading("6.283").is_ok());
        assert!(heading("6.284")
            .unwrap_err()
            .to_string()
            .contains("heading_rad"));
        assert!(heading("-6.284").is_err());
    }

    #[test]
    fn to_toml_round_trips_every_built_in() {
        for (name, text) in BUILT_IN {
            let s = Scene::parse(text, name).unwrap();
            assert_eq!(Scene::parse(&s.to_toml(), name).unwrap(), s, "{name}");
        }
    }

    #[test]
    fn errors_name_the_line() {
        let text = "name = \"x\"\n[surface]\nkind = \"cube\"\n";
        let e = Scene::parse(text, "bad.toml").unwrap_err().to_string();
        assert!(e.contains("bad.toml line 3"), "{e}");
        let e = Scene::parse(
            "name = \"x\"\nrate_hz = 5\n[surface]\nkind = \"plane\"\n",
            "r.toml",
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("rate_hz"), "{e}");
        let e = Scene::parse(
            "name = \"x\"\nbogus = 1\n[surface]\nkind = \"plane\"\n",
            "u.toml",
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("line 2"), "{e}");
    }
}
