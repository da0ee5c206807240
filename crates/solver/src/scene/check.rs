//! Semantic checks of a scene: values alone, then names against a mesh.

use super::error::NameKind;
use super::{Family, JointLaw, Load, Outputs, RuleKind, Scene, SceneError, VtuSections};
use crate::loads::{
    face_section, point_locations, point_off_axis, tolerance, ANTISYMMETRIC_ZERO, RING_ON_AXIS,
};
use crate::material::MaterialError;
use crate::short::Short;
use axijoint_mesh::{CellEdges, CurveSet, JointKind, Mesh};
use std::collections::BTreeSet;

/// Comma-separated names, or `none`.
fn list<'a>(names: impl Iterator<Item = &'a str>) -> String {
    let v: Vec<&str> = names.collect();
    if v.is_empty() {
        "none".into()
    } else {
        v.join(", ")
    }
}

/// The most samples a cut may take (`length / spacing`): a fine cut of a
/// 10 m pile every millimetre takes 10^4; a spacing or an end typed in the
/// wrong unit takes millions, and hours of report.
pub const MAX_CUT_SAMPLES: usize = 100_000;
/// The most angles a cut may list (one CSV file each).
pub const MAX_CUT_ANGLES: usize = 360;

/// [`super::error::nearest`], owned.
fn suggest<'a>(name: &str, known: impl IntoIterator<Item = &'a str>) -> Option<Box<str>> {
    super::error::nearest(name, known).map(Box::from)
}

/// True if `text` has `name` as a whole identifier (letters, digits, `_`).
fn uses_identifier(text: &str, name: &str) -> bool {
    let is_ident = |c: char| c.is_ascii_alphanumeric() || c == '_';
    text.match_indices(name).any(|(at, _)| {
        let before = text[..at].chars().next_back();
        let after = text[at + name.len()..].chars().next();
        !before.is_some_and(is_ident) && !after.is_some_and(is_ident)
    })
}

impl Scene {
    pub(crate) fn invalid(&self, key: impl Into<String>, message: impl Into<String>) -> SceneError {
        SceneError::Invalid {
            path: self.path.clone(),
            key: key.into(),
            message: message.into(),
        }
    }

    fn finite(&self, key: &str, values: &[f64]) -> Result<(), SceneError> {
        match values.iter().find(|v| !v.is_finite()) {
            Some(v) => Err(self.invalid(key, format!("{} is not a finite number", Short(*v)))),
            None => Ok(()),
        }
    }

    /// Checks every value that needs no mesh: units, mesh file and gmsh
    /// parameters (reading the `.geo` to see that it uses each parameter),
    /// materials (E > 0, -1 < nu < 0.5), joints (one form of stiffness:
    /// given springs >= 0, `"rigid"` or a thickness > 0; C >= 0,
    /// 0 <= phi < 90, rule), supports, loads (finite, harmonic within
    /// `harmonics`), sections, solver settings and cuts.
    pub fn check_values(&self) -> Result<(), SceneError> {
        if self.units.consistent() == Some(false) {
            return Err(self.invalid(
                "units",
                format!(
                    "stress unit {} is not force / length^2 = {} / {}^2",
                    self.units.stress, self.units.force, self.units.length
                ),
            ));
        }
        self.check_mesh_source()?;
        if let super::Harmonics::Fixed(m) = self.harmonics {
            if m > super::MAX_HARMONICS && !self.force {
                return Err(self.invalid(
                    "harmonics",
                    format!(
                        "{m}: above {} harmonics a run only costs time and memory ({} factorizations of the mesh); \"auto\" chooses what the answer needs, --force goes on",
                        super::MAX_HARMONICS,
                        m + 1
                    ),
                ));
            }
        }
        if let Some(w) = &self.water {
            self.finite("water.surface_z", &[w.surface_z])?;
            if !(w.unit_weight.is_finite() && w.unit_weight > 0.0) {
                return Err(self.invalid(
                    "water.unit_weight",
                    format!(
                        "{} is not allowed: the unit weight of water > 0",
                        Short(w.unit_weight)
                    ),
                ));
            }
        }
        for (name, mat) in &self.materials {
            if let Err(e) = mat.elastic().validate() {
                let field = match e {
                    MaterialError::Modulus { .. } => "E",
                    MaterialError::Poisson { .. } => "nu",
                };
                return Err(self.invalid(format!("materials.{name}.{field}"), e.to_string()));
            }
            if let Some(init) = &mat.initial_stress {
                self.check_initial_stress(name, init)?;
            }
            if let Some(p) = &mat.plasticity {
                let key = |k: &str| format!("materials.{name}.plasticity.{k}");
                for (k, v) in p.numbers() {
                    self.finite(&key(k), &[v])?;
                }
                let z_ref = match *p {
                    super::Plasticity::Tresca { z_ref, .. } | super::Plasticity::VonMises { z_ref, .. } => {
                        z_ref
                    }
                    super::Plasticity::MohrCoulomb { .. } => 0.0,
                };
                if let Err(e) = p.at(z_ref).validate() {
                    return Err(self.invalid(key(super::Plasticity::key_of(&e)), e.to_string()));
                }
            }
        }
        for (name, joint) in &self.joints {
            self.check_joint(name, joint)?;
        }
        for (i, s) in self.supports.iter().enumerate() {
            if s.fix.is_empty() {
                return Err(self.invalid(
                    format!("supports[{i}].fix"),
                    "fixes nothing: list some of \"r\", \"z\", \"theta\" or write \"all\"",
                ));
            }
        }
        for (i, load) in self.loads.iter().enumerate() {
            self.check_load(i, load)?;
        }
        self.check_load_cases()?;
        self.check_stages()?;
        self.check_motions()?;
        if let Some(sections) = &self.sections {
            let t = &sections.theta_deg;
            match sections.count {
                Some(_) if !t.is_empty() => {
                    return Err(self.invalid("sections", "give either theta_deg or count, not both"));
                }
                Some(0) => return Err(self.invalid("sections.count", "must be at least 1")),
                Some(_) => {}
                None => {
                    self.finite("sections.theta_deg", t)?;
                    let in_range = t.iter().all(|&a| (0.0..360.0).contains(&a));
                    let increasing = t.windows(2).all(|w| w[0] < w[1]);
                    if t.is_empty() || !in_range || !increasing {
                        return Err(self.invalid(
                            "sections.theta_deg",
                            "give at least one angle, in degrees in [0, 360), strictly increasing",
                        ));
                    }
                }
            }
        }
        let eps = self.solver.epsilon;
        if !(eps > 0.0 && eps < 1.0) {
            return Err(self.invalid(
                "solver.epsilon",
                format!(
                    "{} is not allowed: the residual ratio tolerance lies strictly between 0 and 1",
                    Short(eps)
                ),
            ));
        }
        if self.solver.max_iterations == 0 {
            return Err(self.invalid("solver.max_iterations", "must be at least 1"));
        }
        if let VtuSections::Count(n @ 0..3) = self.outputs.vtu_sections {
            return Err(self.invalid(
                "outputs.vtu_sections",
                format!("{n} is not allowed: give at least 3, or \"auto\""),
            ));
        }
        let known = Outputs::VTU_FIELDS;
        if let Some(f) = self
            .outputs
            .vtu_fields
            .iter()
            .find(|f| !known.contains(&f.as_str()))
        {
            return Err(self.invalid(
                "outputs.vtu_fields",
                format!("unknown array '{f}' (known: {})", known.join(", ")),
            ));
        }
        self.check_cuts()
    }

    fn check_mesh_source(&self) -> Result<(), SceneError> {
        let ext = std::path::Path::new(&self.mesh.file)
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        for (name, value) in &self.mesh.parameters {
            self.finite(&format!("mesh.parameters.{name}"), &[*value])?;
        }
        match ext.as_deref() {
            Some("msh") if !self.mesh.parameters.is_empty() => Err(self.invalid(
                "mesh.parameters",
                "a .msh is read as it is: gmsh parameters apply to a .geo only",
            )),
            Some("msh") => Ok(()),
            Some("geo") => {
                let path = self.mesh_path();
                let text = std::fs::read_to_string(&path).map_err(|error| SceneError::Io { path, error })?;
                match self.mesh.parameters.keys().find(|k| !uses_identifier(&text, k)) {
                    Some(name) => Err(self.invalid(
                        format!("mesh.parameters.{name}"),
                        format!(
                            "{} does not use a parameter named '{name}' (gmsh would ignore it)",
                            self.mesh_path().display()
                        ),
                    )),
                    None => Ok(()),
                }
            }
            _ => Err(self.invalid(
                "mesh.file",
                format!("'{}' is neither a .geo nor a .msh file", self.mesh.file),
            )),
        }
    }

    fn check_load_cases(&self) -> Result<(), SceneError> {
        if self.load_cases.is_empty() {
            return Ok(());
        }
        if !self.loads.is_empty() {
            return Err(self.invalid(
                "load_cases",
                "give either `loads` (one case) or `load_cases`, not both",
            ));
        }
        if self.harmonics == crate::scene::Harmonics::Auto {
            return Err(self.invalid(
                "harmonics",
                "load cases share one set of factors: give a number of harmonics, not \"auto\"",
            ));
        }
        for (k, case) in self.load_cases.iter().enumerate() {
            let name = &case.name;
            let valid = !name.is_empty()
                && !name.starts_with('.')
                && name
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || "_-.".contains(c));
            if !valid {
                return Err(self.invalid(
                    format!("load_cases[{k}].name"),
                    format!("'{name}' is not allowed: it names the case's folder (letters, digits, _, - and ., not first)"),
                ));
            }
            if self.load_cases[..k].iter().any(|c| &c.name == name) {
                return Err(self.invalid(format!("load_cases[{k}].name"), format!("'{name}' is used twice")));
            }
            let scene = self.case(k);
            for (i, load) in scene.loads.iter().enumerate() {
                scene.check_load(i, load).map_err(|e| e.in_case(k))?;
            }
        }
        Ok(())
    }

    fn check_initial_stress(&self, name: &str, init: &super::InitialStress) -> Result<(), SceneError> {
        let key = |k: &str| format!("materials.{name}.initial_stress.{k}");
        match *init {
            super::InitialStress::Geostatic {
                surface_z,
                k0,
                surcharge,
            } => {
                self.finite(&key("surface_z"), &[surface_z])?;
                let gamma = self.materials[name].unit_weight;
                if let Some(w) = self.water.filter(|w| gamma > 0.0 && gamma < w.unit_weight) {
                    return Err(self.invalid(
                        format!("materials.{name}.unit_weight"),
                        format!(
                            "{} is below the water's {}: a geostatic soil lighter than water would float (give the saturated unit weight)",
                            Short(gamma),
                            Short(w.unit_weight)
                        ),
                    ));
                }
                if !(k0.is_finite() && k0 >= 0.0) {
                    return Err(self.invalid(key("K0"), format!("{} is not allowed: K0 >= 0", Short(k0))));
                }
                if !(surcharge.is_finite() && surcharge >= 0.0) {
                    return Err(self.invalid(
                        key("surcharge"),
                        format!("{} is not allowed: a surface pressure >= 0", Short(surcharge)),
                    ));
                }
                Ok(())
            }
            super::InitialStress::Constant {
                sigma_r,
                sigma_z,
                sigma_theta,
                tau_rz,
            } => self.finite(
                &format!("materials.{name}.initial_stress"),
                &[sigma_r, sigma_z, sigma_theta, tau_rz],
            ),
            super::InitialStress::Gravity => Ok(()),
        }
    }

    /// The form of joint `name`'s stiffness, or an error at its key
    /// ([`super::JointConfig::stiffness`]).
    pub fn joint_stiffness(
        &self,
        name: &str,
        joint: &super::JointConfig,
    ) -> Result<super::JointStiffness, SceneError> {
        joint
            .stiffness()
            .map_err(|(k, message)| self.invalid(format!("joints.{name}.{k}"), message))
    }

    fn check_joint(&self, name: &str, joint: &super::JointConfig) -> Result<(), SceneError> {
        let key = |k: &str| format!("joints.{name}.{k}");
        if let Some(t) = &joint.initial_traction {
            self.finite(&key("initial_traction"), t)?;
            if !self.has_initial_phase() {
                return Err(self.invalid(
                    key("initial_traction"),
                    "needs an initial phase: give some material an `initial_stress` (e.g. {\"type\": \"gravity\"})",
                ));
            }
        }
        match self.joint_stiffness(name, joint)? {
            super::JointStiffness::Given(springs) => {
                if let Err(crate::elements::JointError::Stiffness { name: k, value }) = springs.validate() {
                    return Err(self.invalid(
                        key(k),
                        format!(
                            "{} is not allowed: a stiffness is a finite number >= 0",
                            Short(value)
                        ),
                    ));
                }
            }
            super::JointStiffness::Thickness(t) if !(t.is_finite() && t > 0.0) => {
                return Err(self.invalid(
                    key("stiffness.thickness"),
                    format!(
                        "{} is not allowed: the interface layer's thickness is a length > 0",
                        Short(t)
                    ),
                ));
            }
            super::JointStiffness::Rigid
                if joint.law != JointLaw::Linear && self.solver.method != super::SolverMethod::Newton =>
            {
                return Err(self.invalid(
                    key("stiffness"),
                    "a rigid joint (the default when no stiffness is given) with a nonlinear law needs `solver.method` \"newton\" (the default): the paper's and Anderson's iterations keep the joint's stiffness in K_m and crawl on a stiff joint (docs/stability.md); give `k_xi`, `k_eta`, `k_theta` of about E / h or less, or a `thickness`, for those methods",
                ));
            }
            _ => {}
        }
        if joint.bottom.is_some() != joint.top.is_some() {
            let missing = if joint.bottom.is_none() { "bottom" } else { "top" };
            return Err(self.invalid(
                key(missing),
                "give both `bottom` and `top` (physical surfaces), or neither",
            ));
        }
        if let JointLaw::MohrCoulomb(mc) = joint.law {
            let law = |k: &str| key(&format!("law.{k}"));
            if !(mc.cohesion.is_finite() && mc.cohesion >= 0.0) {
                return Err(self.invalid(
                    law("cohesion"),
                    format!("{} is not allowed: C >= 0", Short(mc.cohesion)),
                ));
            }
            if !(0.0..90.0).contains(&mc.friction_deg) {
                return Err(self.invalid(
                    law("friction_deg"),
                    format!(
                        "{} is not allowed: the friction angle lies in [0, 90) degrees",
                        mc.friction_deg
                    ),
                ));
            }
            let t = mc.tensile_strength;
            if !(t.is_finite() && t >= 0.0) {
                return Err(self.invalid(
                    law("tensile_strength"),
                    format!("{} is not allowed: it must be >= 0", Short(t)),
                ));
            }
            let apex = mc.cohesion / mc.tan_phi();
            if t > apex {
                return Err(self.invalid(
                    law("tensile_strength"),
                    format!("{} lies beyond the Mohr-Coulomb apex C / tan(phi) = {}, where the shear strength is zero", Short(t), Short(apex)),
                ));
            }
        }
        match (joint.rule, joint.points) {
            (RuleKind::Paper, Some(_)) => Err(self.invalid(
                key("points"),
                "the paper's rule has one point at the element centre: leave out `points`",
            )),
            (_, Some(_)) => {
                let rule = joint.rule(JointKind::Lin4);
                rule.validate()
                    .map_err(|e| self.invalid(key("points"), e.to_string()))
            }
            (_, None) => Ok(()),
        }
    }

    pub(super) fn check_load(&self, i: usize, load: &Load) -> Result<(), SceneError> {
        let key = |k: &str| format!("loads[{i}].{k}");
        let m = load.max_harmonic();
        let harmonic_key = match load {
            Load::Traction(_) | Load::Ring(_) => "harmonic",
            Load::Resultant(_) | Load::Point(_) => "force",
            Load::Motion(_) => "displacement",
        };
        if matches!(self.harmonics, crate::scene::Harmonics::Fixed(top) if m > top) {
            return Err(self.invalid(
                key(harmonic_key),
                format!(
                    "the load has a part of harmonic {m} but `harmonics` is {}",
                    self.harmonics()
                ),
            ));
        }
        match load {
            Load::Traction(l) => {
                for (name, t) in ["t_r", "t_z", "t_theta"].iter().zip(&l.t) {
                    self.finite(&key(name), &[t.c, t.r, t.z])?;
                }
                if l.harmonic == 0 && l.family == Family::Antisymmetric {
                    return Err(self.invalid(key("family"), ANTISYMMETRIC_ZERO));
                }
            }
            Load::Resultant(l) => {
                self.finite(&key("force"), &l.force)?;
                self.finite(&key("at_z"), l.at_z.as_slice())?;
                self.finite(&key("torque"), &[l.torque])?;
                self.finite(&key("moment"), &l.moment)?;
            }
            Load::Ring(l) => {
                for (name, f) in ["f_r", "f_z", "f_theta"].iter().zip(&l.f) {
                    self.finite(&key(name), &[*f])?;
                }
                if l.harmonic == 0 && l.family == Family::Antisymmetric {
                    return Err(self.invalid(key("family"), ANTISYMMETRIC_ZERO));
                }
            }
            Load::Point(l) => self.finite(&key("force"), &l.force)?,
            Load::Motion(l) => {
                self.finite(&key("displacement"), &l.displacement)?;
                self.finite(&key("rotation"), &l.rotation)?;
                self.finite(&key("at_z"), l.at_z.as_slice())?;
            }
        }
        if load.on().is_empty() {
            return Err(self.invalid(key("on"), "empty name"));
        }
        Ok(())
    }

    /// Every cut's name, ends, spacing (at most [`MAX_CUT_SAMPLES`] samples),
    /// component and angles (at most [`MAX_CUT_ANGLES`]).
    fn check_cuts(&self) -> Result<(), SceneError> {
        let mut names = BTreeSet::new();
        for (i, cut) in self.cuts.iter().enumerate() {
            let key = |k: &str| format!("cuts[{i}].{k}");
            let ok_char = |c: char| c.is_ascii_alphanumeric() || "-_.".contains(c);
            if cut.name.is_empty() || !cut.name.chars().all(ok_char) {
                return Err(self.invalid(
                    key("name"),
                    format!(
                        "'{}': use letters, digits, '-', '_' or '.' (it names output files)",
                        cut.name
                    ),
                ));
            }
            if !names.insert(cut.name.as_str()) {
                return Err(self.invalid(key("name"), format!("cut '{}' is named twice", cut.name)));
            }
            for (k, p) in [("from", cut.from), ("to", cut.to)] {
                self.finite(&key(k), &p)?;
                if p[0] < 0.0 {
                    return Err(self.invalid(
                        key(k),
                        format!("r = {} < 0: the mesh lives in r >= 0", Short(p[0])),
                    ));
                }
            }
            if cut.from == cut.to {
                return Err(self.invalid(key("to"), "the cut has zero length (`from` equals `to`)"));
            }
            if !(cut.spacing.is_finite() && cut.spacing > 0.0) {
                return Err(self.invalid(
                    key("spacing"),
                    format!("{} is not allowed: it must be > 0", Short(cut.spacing)),
                ));
            }
            let length = (cut.to[0] - cut.from[0]).hypot(cut.to[1] - cut.from[1]);
            let samples = length / cut.spacing;
            if samples > MAX_CUT_SAMPLES as f64 {
                return Err(self.invalid(
                    key("spacing"),
                    format!(
                        "{} along a cut {} long gives {} samples, at most {MAX_CUT_SAMPLES}: a units slip? (a spacing in mm, a point in mm)",
                        Short(cut.spacing),
                        Short(length),
                        Short(samples.ceil())
                    ),
                ));
            }
            if cut.theta_deg.len() > MAX_CUT_ANGLES {
                return Err(self.invalid(
                    key("theta_deg"),
                    format!(
                        "{} angles, at most {MAX_CUT_ANGLES} (each one is a CSV file)",
                        cut.theta_deg.len()
                    ),
                ));
            }
            if cut.component_index().is_none() {
                return Err(self.invalid(
                    key("component"),
                    format!(
                        "'{}' is not a stress component: sigma_r, sigma_z, sigma_theta, tau_rz, tau_rtheta or tau_ztheta",
                        cut.component
                    ),
                ));
            }
            self.finite(&key("theta_deg"), &cut.theta_deg)?;
            if cut.theta_deg.is_empty() {
                return Err(self.invalid(key("theta_deg"), "give at least one angle"));
            }
        }
        Ok(())
    }

    /// The physical curve `name`, or an error at `key` listing the curves.
    pub(crate) fn curve<'m>(
        &self,
        mesh: &'m Mesh,
        name: &str,
        key: &str,
    ) -> Result<&'m CurveSet, SceneError> {
        mesh.curve(name).ok_or_else(|| SceneError::UnknownName {
            path: self.path.clone(),
            key: key.into(),
            what: NameKind::Curve,
            name: name.into(),
            known: list(mesh.curves.iter().map(|c| c.name.as_str())),
            suggestion: suggest(name, mesh.curves.iter().map(|c| c.name.as_str())),
        })
    }

    /// The nodes of physical point `name`, or an error at `key` listing the points.
    pub(crate) fn point_nodes<'m>(
        &self,
        mesh: &'m Mesh,
        name: &str,
        key: &str,
    ) -> Result<&'m [usize], SceneError> {
        mesh.point(name)
            .map(|p| p.nodes.as_slice())
            .ok_or_else(|| SceneError::UnknownName {
                path: self.path.clone(),
                key: key.into(),
                what: NameKind::Point,
                name: name.into(),
                known: list(mesh.points.iter().map(|p| p.name.as_str())),
                suggestion: suggest(name, mesh.points.iter().map(|p| p.name.as_str())),
            })
    }

    fn surface(&self, mesh: &Mesh, name: &str, key: String) -> Result<(), SceneError> {
        match mesh.body(name) {
            Some(_) => Ok(()),
            None => Err(SceneError::UnknownName {
                path: self.path.clone(),
                key,
                what: NameKind::Surface,
                name: name.into(),
                known: list(mesh.bodies.iter().map(|b| b.name.as_str())),
                suggestion: suggest(name, mesh.bodies.iter().map(|b| b.name.as_str())),
            }),
        }
    }

    /// [`Scene::check_values`], then every name against `mesh` (before or
    /// after joint insertion): each material's surface exists and each
    /// surface has a material; joint curves and their sides, support and
    /// load targets exist; every line element of a joint, support or load
    /// curve is an edge of a 2D element ([`CellEdges::check`]); a
    /// resultant's curve is a flat face perpendicular to the axis; ring
    /// loads are off the axis and point loads on it.
    pub fn check(&self, mesh: &Mesh) -> Result<(), SceneError> {
        self.check_values()?;
        let edges = CellEdges::new(mesh);
        let on_edges = |curve: &CurveSet, key: &str| {
            edges
                .check(curve, &self.mesh_path())
                .map_err(|e| self.invalid(key, e.to_string()))
        };
        for name in self.materials.keys() {
            self.surface(mesh, name, format!("materials.{name}"))?;
        }
        self.check_strength_with_depth(mesh)?;
        if let Some(body) = mesh.bodies.iter().find(|b| !self.materials.contains_key(&b.name)) {
            return Err(self.invalid(
                "materials",
                format!(
                    "physical surface '{}' has no material (materials given: {})",
                    body.name,
                    list(self.materials.keys().map(String::as_str))
                ),
            ));
        }
        for (name, joint) in &self.joints {
            let key = format!("joints.{name}");
            on_edges(self.curve(mesh, name, &key)?, &key)?;
            for (side, body) in [("bottom", &joint.bottom), ("top", &joint.top)] {
                if let Some(body) = body {
                    self.surface(mesh, body, format!("joints.{name}.{side}"))?;
                }
            }
        }
        for (i, s) in self.supports.iter().enumerate() {
            if let Some(curve) = mesh.curve(&s.on) {
                on_edges(curve, &format!("supports[{i}].on"))?;
            } else if mesh.point(&s.on).is_none() {
                let known = || {
                    mesh.curves
                        .iter()
                        .map(|c| c.name.as_str())
                        .chain(mesh.points.iter().map(|p| p.name.as_str()))
                };
                return Err(SceneError::UnknownName {
                    path: self.path.clone(),
                    key: format!("supports[{i}].on"),
                    what: NameKind::CurveOrPoint,
                    name: s.on.clone(),
                    known: list(known()),
                    suggestion: suggest(&s.on, known()),
                });
            }
        }
        for (i, name) in self.outputs.members.iter().enumerate() {
            self.surface(mesh, name, format!("outputs.members[{i}]"))?;
        }
        for k in 0..self.load_cases.len() {
            self.case(k).check_loads_on(mesh).map_err(|e| e.in_case(k))?;
        }
        for (k, s) in self.stages.iter().enumerate() {
            self.stage_scene(s.loads.clone())
                .check_loads_on(mesh)
                .map_err(|e| e.in_stage(k, "loads"))?;
            if let Some(c) = &s.cyclic {
                self.stage_scene(c.loads.clone())
                    .check_loads_on(mesh)
                    .map_err(|e| e.in_stage(k, "cyclic.loads"))?;
            }
        }
        self.check_loads_on(mesh)
    }

    /// The loads' names and faces against the mesh.
    fn check_loads_on(&self, mesh: &Mesh) -> Result<(), SceneError> {
        let edges = CellEdges::new(mesh);
        let on_edges = |curve: &CurveSet, key: &str| {
            edges
                .check(curve, &self.mesh_path())
                .map_err(|e| self.invalid(key, e.to_string()))
        };
        let tol = tolerance(mesh);
        for (i, load) in self.loads.iter().enumerate() {
            let key = format!("loads[{i}].on");
            match load {
                Load::Traction(l) => {
                    on_edges(self.curve(mesh, &l.on, &key)?, &key)?;
                }
                Load::Resultant(l) => {
                    let curve = self.curve(mesh, &l.on, &key)?;
                    on_edges(curve, &key)?;
                    face_section(mesh, curve).map_err(|e| self.invalid(key, e))?;
                }
                Load::Ring(l) => {
                    let nodes = self.point_nodes(mesh, &l.on, &key)?;
                    if point_locations(mesh, nodes).iter().any(|(r, _)| *r <= tol) {
                        return Err(self.invalid(key, RING_ON_AXIS));
                    }
                }
                Load::Point(l) => {
                    let nodes = self.point_nodes(mesh, &l.on, &key)?;
                    if let Some((r, _)) = point_locations(mesh, nodes).into_iter().find(|(r, _)| *r > tol) {
                        return Err(self.invalid(key, point_off_axis(r)));
                    }
                }
                Load::Motion(l) => {
                    on_edges(self.curve(mesh, &l.on, &key)?, &key)?;
                }
            }
        }
        Ok(())
    }
}

impl Scene {
    /// A strength that grows with depth must stay >= 0 over its body:
    /// `c_u(z)` at the body's highest node (the strength is linear in z,
    /// so the highest or lowest node is where it is least).
    fn check_strength_with_depth(&self, mesh: &Mesh) -> Result<(), SceneError> {
        for (b, body) in mesh.bodies.iter().enumerate() {
            let Some(p) = self.materials.get(&body.name).and_then(|m| m.plasticity) else {
                continue;
            };
            let zs = mesh
                .cells
                .iter()
                .filter(|c| c.body == b)
                .flat_map(|c| c.nodes.iter().map(|&k| mesh.nodes[k][1]));
            let (lo, hi) = zs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), z| {
                (a.min(z), b.max(z))
            });
            for z in [lo, hi].into_iter().filter(|z| z.is_finite()) {
                if let Err(e) = p.at(z).validate() {
                    return Err(self.invalid(
                        format!(
                            "materials.{}.plasticity.{}",
                            body.name,
                            super::Plasticity::key_of(&e)
                        ),
                        format!(
                            "at z = {} in '{}': {e} (c_u(z) = c_u + gradient (z_ref - z))",
                            Short(z),
                            body.name
                        ),
                    ));
                }
            }
        }
        Ok(())
    }
}
