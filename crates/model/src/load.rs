//! Loading a scene from RON, validating it, and `--set PATH=VALUE` overrides.

use std::collections::HashSet;
use std::path::Path;

use flexmbd_core::{Dim, InvalidValue, require_non_negative, require_positive};
use flexmbd_fe::reduced::Dof;
use serde_json::Value;

use crate::error::ModelError;
use crate::scene::{
    Body, BodyModel, GROUND, Joint, JointKind, Marker, Scene, Sensor, SensorKind, Stiffening,
};

impl Scene {
    /// Parse RON text; `origin` names the file in errors. Not validated.
    pub fn from_ron_str(text: &str, origin: &str) -> Result<Scene, ModelError> {
        let mut scene: Scene = ron::from_str(text).map_err(|e| ModelError::Parse {
            file: origin.to_string(),
            line: e.span.start.line,
            column: e.span.start.col,
            message: e.code.to_string(),
        })?;
        scene.origin = origin.to_string();
        scene.source = text.to_string();
        for b in &mut scene.bodies {
            if let BodyModel::Beam(spec) = &mut b.model {
                spec.origin = format!("{origin}: bodies[{}]", b.name);
            }
        }
        Ok(scene)
    }

    /// Read, parse and validate a scene file.
    pub fn load(path: impl AsRef<Path>) -> Result<Scene, ModelError> {
        let path = path.as_ref();
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|source| ModelError::Io {
            file: file.clone(),
            source,
        })?;
        let scene = Scene::from_ron_str(&text, &file)?;
        scene.validate()?;
        Ok(scene)
    }

    /// The refusal of a value, with the line of its field in the scene text (found by
    /// [`crate::lines::line_of`] from the field path).
    pub fn invalid(&self, e: InvalidValue) -> ModelError {
        ModelError::Invalid {
            file: self.origin.clone(),
            line: crate::lines::line_of(&self.source, &e.field),
            error: e,
        }
    }

    /// The refusal of a name given twice in the list at `list` (e.g. `bodies`,
    /// `bodies[crank].markers`), with the line where it is given again.
    pub(crate) fn repeated_name(&self, list: &str, name: &str, what: &str) -> ModelError {
        ModelError::Invalid {
            file: self.origin.clone(),
            line: crate::lines::line_of_repeated(&self.source, list, name),
            error: InvalidValue::new(
                format!("{list}[{name}].name"),
                name,
                format!("duplicate {what} name"),
            ),
        }
    }

    /// Refuse the first marker of `markers` (one body's, or the ground's, in the list at
    /// `list`) whose name an earlier one already has.
    fn unique_marker_names(&self, list: &str, markers: &[Marker]) -> Result<(), ModelError> {
        let mut names = HashSet::new();
        for m in markers {
            if !names.insert(m.name.as_str()) {
                return Err(self.repeated_name(list, &m.name, "marker"));
            }
        }
        Ok(())
    }

    /// Check names, references, values and sizes, once for every formulation. Errors name
    /// the file, the line of the field (when found in the scene text) and the field.
    ///
    /// The parts of the scene are checked in a fixed order (solver, gravity, bodies,
    /// ground, joints, drivers, forces, constraints, sensors, sizes, joined markers) and the first error
    /// found is returned, so that a scene with several mistakes always reports the same
    /// one. Every number is checked against its range in [`flexmbd_fe::bounds`] (finite, and
    /// small enough that the arithmetic stays finite), so no formulation sees a NaN.
    pub fn validate(&self) -> Result<(), ModelError> {
        self.check_solver()?;
        self.check_gravity()?;
        self.check_bodies()?;
        self.unique_marker_names("ground", &self.ground)?;
        self.check_ground_values()?;
        self.check_joints()?;
        self.check_drivers()?;
        self.check_one_driver_per_joint()?;
        self.check_roads()?;
        self.check_forces()?;
        self.check_constraints()?;
        self.check_sensors()?;
        self.check_inputs()?;
        self.check_sizes()?;
        self.check_joined_markers_coincide()
    }

    /// The solver settings: positive step, duration and optional output interval (the step
    /// count is bounded by the run), a tolerance in (0, 1] and a penalty in range, and a
    /// Newton iteration limit of at least 1 and at most
    /// [`flexmbd_fe::bounds::MAX_NEWTON_ITERATIONS`] (a diverging step must end).
    fn check_solver(&self) -> Result<(), ModelError> {
        let s = &self.solver;
        let time = flexmbd_fe::bounds::SOLVER_TIME;
        self.in_range(time, "solver.step", s.step)?;
        self.in_range(time, "solver.duration", s.duration)?;
        if let Some(o) = s.output_interval {
            self.in_range(time, "solver.output_interval", o)?;
        }
        self.in_range(
            flexmbd_fe::bounds::NEWTON_TOLERANCE,
            "solver.newton_tolerance",
            s.newton_tolerance,
        )?;
        let most = flexmbd_fe::bounds::MAX_NEWTON_ITERATIONS;
        if !(1..=most).contains(&s.max_iterations) {
            return Err(self.invalid(InvalidValue::new(
                "solver.max_iterations",
                s.max_iterations,
                format!("must be in 1..={most} (a Newton iteration limit per step)"),
            )));
        }
        if let Some(p) = s.penalty {
            self.in_range(flexmbd_fe::bounds::PENALTY, "solver.penalty", p)?;
        }
        Ok(())
    }

    /// Each body in turn; body names must be unique and none may be `ground`.
    fn check_bodies(&self) -> Result<(), ModelError> {
        let mut body_names = HashSet::new();
        for b in &self.bodies {
            if b.name == GROUND {
                return Err(self.invalid(InvalidValue::new(
                    "bodies[ground].name",
                    GROUND,
                    "`ground` is the fixed body; choose another name",
                )));
            }
            if !body_names.insert(b.name.as_str()) {
                return Err(self.repeated_name("bodies", &b.name, "body"));
            }
            self.unique_marker_names(&format!("bodies[{}].markers", b.name), &b.markers)?;
            self.check_body_values(b)?;
            self.check_initial_modes(b)?;
            self.check_body_model(b)?;
        }
        Ok(())
    }

    /// A body's initial modal coordinates: no more than it has (a flexible beam's
    /// boundary and normal modes, none otherwise), and all finite.
    fn check_initial_modes(&self, b: &Body) -> Result<(), ModelError> {
        let field = format!("bodies[{}].initial_modes", b.name);
        let n_modes = match &b.model {
            BodyModel::Beam(spec) if b.flexible => {
                spec.boundary.len().saturating_add(spec.normal_modes)
            }
            _ => b.declared_modes(),
        };
        if b.initial_modes.len() > n_modes {
            return Err(self.invalid(InvalidValue::new(
                field,
                format!("{:?}", b.initial_modes),
                format!("the body has {n_modes} modal coordinates"),
            )));
        }
        if let Some(v) = b.initial_modes.iter().find(|v| !v.is_finite()) {
            return Err(self.invalid(InvalidValue::new(field, v, "must be finite")));
        }
        Ok(())
    }

    /// A body's model: a rigid body's positive mass and non-negative principal inertias,
    /// or a beam of the scene's dimension whose finite-element spec is itself valid.
    fn check_body_model(&self, b: &Body) -> Result<(), ModelError> {
        let f = |field: &str| format!("bodies[{}].{field}", b.name);
        match &b.model {
            BodyModel::Rigid { mass, inertia, .. } => {
                require_positive(&f("model.Rigid.mass"), *mass).map_err(|e| self.invalid(e))?;
                let t = inertia.tensor();
                for k in 0..3 {
                    require_non_negative(&f("model.Rigid.inertia"), t[(k, k)])
                        .map_err(|e| self.invalid(e))?;
                }
            }
            BodyModel::Beam(spec) => {
                if spec.dim != self.dim {
                    return Err(self.invalid(InvalidValue::new(
                        f("model.Beam.dim"),
                        format!("{:?}", spec.dim),
                        format!("the scene is {:?}", self.dim),
                    )));
                }
                spec.validate()
                    .map_err(|source| self.fe_error(&b.name, source))?;
            }
            BodyModel::Imported(spec) => {
                let solid = matches!(
                    spec.source,
                    flexmbd_fe::imported::ImportSource::Solid { .. }
                );
                let stiffening = self.solver.stiffening;
                if b.flexible
                    && solid
                    && !matches!(stiffening, Stiffening::Linear | Stiffening::Fnl1)
                {
                    return Err(ModelError::Unsupported(format!(
                        "{}: body `{}` is a solid (source: Solid), whose geometric stiffening is \
                         FNL1 only: the stiffening methods FNL2, FS0 and substructuring are beam \
                         methods and are refused for it (use `stiffening: Fnl1` or `Linear`)",
                        self.origin, b.name
                    )));
                }
                if b.flexible && !solid && stiffening != Stiffening::Linear {
                    return Err(ModelError::Unsupported(format!(
                        "{}: body `{}` is an imported FE model, which has no element data: \
                         the stiffening methods FNL1, FNL2, FS0 and substructuring are refused \
                         for it (use `stiffening: Linear`; a solid mesh, source: Solid, takes \
                         FNL1)",
                        self.origin, b.name
                    )));
                }
                if self.dim != Dim::Spatial {
                    return Err(self.invalid(InvalidValue::new(
                        f("model.Imported"),
                        "an imported FE body",
                        "an imported body is spatial: the scene must be 3D",
                    )));
                }
            }
        }
        Ok(())
    }

    /// The refusal of body `body`'s FE model, with the line of the refused field.
    pub(crate) fn fe_error(&self, body: &str, source: flexmbd_fe::FeError) -> ModelError {
        let line = match &source {
            flexmbd_fe::FeError::Invalid(e) => crate::lines::line_of(
                &self.source,
                &format!("bodies[{body}].model.Beam.{}", e.field),
            ),
            _ => None,
        };
        ModelError::Fe {
            file: self.origin.clone(),
            line,
            body: body.to_string(),
            source: Box::new(source),
        }
    }

    /// Each joint in turn; joint names must be unique.
    fn check_joints(&self) -> Result<(), ModelError> {
        let mut joint_names = HashSet::new();
        for j in &self.joints {
            if !joint_names.insert(j.name.as_str()) {
                return Err(self.repeated_name("joints", &j.name, "joint"));
            }
            self.check_joint(j)?;
            self.check_joint_axes(&j.name, &j.kind)?;
        }
        Ok(())
    }

    /// One joint: existing markers on two different bodies, a Free joint only from the
    /// ground, and no spatial-only kind in a planar scene.
    fn check_joint(&self, j: &Joint) -> Result<(), ModelError> {
        let item = |f: &str| format!("joints[{}].{f}", j.name);
        self.check_marker(&item("body1"), &j.body1, &item("marker1"), &j.marker1)?;
        self.check_marker(&item("body2"), &j.body2, &item("marker2"), &j.marker2)?;
        if j.body1 == j.body2 {
            return Err(self.invalid(InvalidValue::new(
                item("body2"),
                &j.body2,
                "a joint needs two different bodies",
            )));
        }
        if matches!(j.kind, JointKind::Free) && j.body1 != GROUND {
            return Err(self.invalid(InvalidValue::new(
                item("body1"),
                &j.body1,
                "a Free joint joins a floating base (body2) to the ground: body1 must be `ground`",
            )));
        }
        let planar = self.dim == flexmbd_core::Dim::Planar;
        let spatial_only = matches!(
            j.kind,
            JointKind::Spherical | JointKind::Universal { .. } | JointKind::Cylindrical { .. }
        );
        if planar && spatial_only {
            return Err(self.invalid(InvalidValue::new(
                item("kind"),
                format!("{:?}", j.kind),
                "not a planar joint",
            )));
        }
        Ok(())
    }

    /// Each driver must drive an existing joint with a single coordinate (revolute or
    /// prismatic),
    /// with its law's parameters in range (a SpinUp law needs a positive ramp time).
    fn check_drivers(&self) -> Result<(), ModelError> {
        for d in &self.drivers {
            let Some(j) = self.joints.iter().find(|j| j.name == d.joint) else {
                return Err(self.missing(format!("drivers[{}].joint", d.name), "joint", &d.joint));
            };
            if !has_one_coordinate(&j.kind) {
                return Err(self.invalid(InvalidValue::new(
                    format!("drivers[{}].joint", d.name),
                    &d.joint,
                    format!(
                        "only revolute (angle) and prismatic (distance) joints can be driven; \
                         `{}` is {}",
                        d.joint,
                        j.kind.kind_name()
                    ),
                )));
            }
            self.check_law(&d.name, &d.law)?;
        }
        Ok(())
    }

    /// Each sensor in turn; sensor names must be unique and none may be `t` (the time
    /// column of the output).
    fn check_sensors(&self) -> Result<(), ModelError> {
        let mut sensor_names = HashSet::new();
        for sn in &self.sensors {
            if sn.name == "t" {
                return Err(self.invalid(InvalidValue::new(
                    "sensors[t].name",
                    "t",
                    "`t` is the time column of the output; choose another name",
                )));
            }
            if !sensor_names.insert(sn.name.as_str()) {
                return Err(self.repeated_name("sensors", &sn.name, "sensor"));
            }
            self.check_sensor(sn)?;
        }
        Ok(())
    }

    /// One sensor: a displacement only from a Position sensor, and what its kind
    /// measures must exist (marker and frame, a revolute or prismatic joint, modal index).
    fn check_sensor(&self, sn: &Sensor) -> Result<(), ModelError> {
        let item = |f: &str| format!("sensors[{}].{f}", sn.name);
        if sn.displacement && !matches!(sn.kind, SensorKind::Position { .. }) {
            return Err(self.invalid(InvalidValue::new(
                item("displacement"),
                true,
                "only a Position sensor can report a displacement",
            )));
        }
        if let Some((body, marker, frame)) = sn.kind.marker() {
            self.check_marker(&item("body"), body, &item("marker"), marker)?;
            if let Some(fr) = frame
                && fr != GROUND
                && !self.bodies.iter().any(|b| b.name == fr)
            {
                return Err(self.missing(item("frame"), "body", fr));
            }
        }
        match &sn.kind {
            SensorKind::JointCoordinate { joint } => {
                let Some(j) = self.joints.iter().find(|j| &j.name == joint) else {
                    return Err(self.missing(item("joint"), "joint", joint));
                };
                if !has_one_coordinate(&j.kind) {
                    return Err(self.invalid(InvalidValue::new(
                        item("joint"),
                        joint,
                        format!(
                            "a joint coordinate is defined for revolute (angle) and prismatic \
                             (slide) joints only; `{joint}` is {} (use Position/Velocity sensors)",
                            j.kind.kind_name()
                        ),
                    )));
                }
            }
            SensorKind::Modal { body, index } => self.check_modal_sensor(&sn.name, body, *index)?,
            SensorKind::Angle { body, .. } => {
                if !self.bodies.iter().any(|b| &b.name == body) {
                    return Err(self.missing(item("body"), "body", body));
                }
            }
            SensorKind::ElementForce { force, .. } => {
                if !self.forces.iter().any(|f| f.name() == force) {
                    return Err(self.missing(item("force"), "force element", force));
                }
            }
            SensorKind::Stress { body, .. } => {
                if !self.bodies.iter().any(|b| &b.name == body) {
                    return Err(self.missing(item("body"), "body", body));
                }
            }
            SensorKind::InterfaceForce { body, .. } if body == GROUND => {
                return Err(self.invalid(InvalidValue::new(
                    item("body"),
                    body,
                    "an interface force acts on a moving body; name the body the joints and \
                     force elements at the marker act on",
                )));
            }
            SensorKind::Position { .. }
            | SensorKind::Velocity { .. }
            | SensorKind::InterfaceForce { .. }
            | SensorKind::Energy => {}
        }
        Ok(())
    }

    /// A Modal sensor's body must exist and `index` must be one of its modal coordinates
    /// (a flexible beam's boundary, normal and axial modes; a rigid body has none).
    fn check_modal_sensor(&self, sensor: &str, body: &str, index: usize) -> Result<(), ModelError> {
        let item = |f: &str| format!("sensors[{sensor}].{f}");
        let Some(b) = self.bodies.iter().find(|b| b.name == body) else {
            return Err(self.missing(item("body"), "body", body));
        };
        let n = b.declared_modes();
        if index >= n {
            return Err(self.invalid(InvalidValue::new(
                item("index"),
                index,
                format!("body `{body}` has {n} modal coordinates"),
            )));
        }
        Ok(())
    }

    pub(crate) fn missing(&self, item: String, kind: &'static str, name: &str) -> ModelError {
        let known: Vec<&str> = match kind {
            "body" => std::iter::once(GROUND)
                .chain(self.bodies.iter().map(|b| b.name.as_str()))
                .collect(),
            "joint" => self.joints.iter().map(|j| j.name.as_str()).collect(),
            "force element" => self.forces.iter().map(|f| f.name()).collect(),
            _ => Vec::new(),
        };
        let hint = if !known.is_empty() && known.len() <= 12 {
            format!(" (known: {})", known.join(", "))
        } else {
            String::new()
        };
        ModelError::Missing {
            file: self.origin.clone(),
            line: crate::lines::line_of(&self.source, &item),
            item,
            kind,
            name: name.to_string(),
            hint,
        }
    }

    pub(crate) fn check_marker(
        &self,
        body_item: &str,
        body: &str,
        marker_item: &str,
        marker: &str,
    ) -> Result<(), ModelError> {
        let markers: Vec<&str> = if body == GROUND {
            self.ground.iter().map(|m| m.name.as_str()).collect()
        } else {
            match self.bodies.iter().find(|b| b.name == body) {
                Some(b) => b.markers.iter().map(|m| m.name.as_str()).collect(),
                None => return Err(self.missing(body_item.to_string(), "body", body)),
            }
        };
        if !markers.contains(&marker) {
            let hint = format!(" (markers of `{body}`: {})", markers.join(", "));
            return Err(ModelError::Missing {
                file: self.origin.clone(),
                line: crate::lines::line_of(&self.source, marker_item),
                item: marker_item.to_string(),
                kind: "marker",
                name: marker.to_string(),
                hint,
            });
        }
        Ok(())
    }

    /// Apply `PATH=VALUE` overrides: `PATH` is a dotted path of field names; in a list of
    /// named items (bodies, joints, sensors, forces, constraints, ...) an item is selected by
    /// its `name` (an enum item by the `name` among its fields, whose fields the path then
    /// continues with: `constraints.tie_rod.length=0.3`)
    /// (e.g. `bodies.crank1.flexible=true`, `solver.step=5e-4`,
    /// `bodies.bar.model.Beam.material.young_modulus=7e10`). The value must be a scalar of
    /// the field's type. The scene is validated again afterwards.
    pub fn apply_sets(&mut self, sets: &[(String, String)]) -> Result<(), ModelError> {
        if sets.is_empty() {
            return Ok(());
        }
        let (origin, source) = (self.origin.clone(), self.source.clone());
        let mut tree = serde_json::to_value(&*self).map_err(|e| ModelError::Set {
            path: String::new(),
            message: e.to_string(),
        })?;
        for (path, value) in sets {
            set_path(&mut tree, path, value)?;
        }
        let mut scene: Scene = serde_json::from_value(tree).map_err(|e| ModelError::Set {
            path: sets
                .iter()
                .map(|(p, v)| format!("{p}={v}"))
                .collect::<Vec<_>>()
                .join(" "),
            message: e.to_string(),
        })?;
        scene.origin = origin;
        scene.source = source;
        for b in &mut scene.bodies {
            if let BodyModel::Beam(spec) = &mut b.model {
                spec.origin = format!("{}: bodies[{}]", scene.origin, b.name);
            }
        }
        scene.validate()?;
        *self = scene;
        Ok(())
    }
}

impl Scene {
    /// The undeformed position of `marker` of `body` (or a ground marker) at t = 0, in
    /// ground components, or in `frame`'s body axes relative to its origin.
    pub fn undeformed_position(
        &self,
        body: &str,
        marker: &str,
        frame: Option<&str>,
    ) -> Option<nalgebra::Vector3<f64>> {
        let placement = |name: &str| {
            self.bodies
                .iter()
                .find(|b| b.name == name)
                .map(|b| (b.origin.vec(), b.orientation.matrix()))
        };
        let global = if body == GROUND {
            self.ground
                .iter()
                .find(|m| m.name == marker)?
                .position
                .vec()
        } else {
            let b = self.bodies.iter().find(|b| b.name == body)?;
            let (o, a) = placement(body)?;
            o + a * b.markers.iter().find(|m| m.name == marker)?.position.vec()
        };
        match frame {
            None | Some(GROUND) => Some(global),
            Some(f) => {
                let (o, a) = placement(f)?;
                Some(a.transpose() * (global - o))
            }
        }
    }

    /// Per sensor, the value to subtract from what the formulation reports: the undeformed
    /// position component for `displacement` sensors, 0 otherwise.
    pub fn sensor_offsets(&self) -> Vec<f64> {
        self.sensors
            .iter()
            .map(|s| match (&s.kind, s.displacement) {
                (
                    SensorKind::Position {
                        body,
                        marker,
                        component,
                        frame,
                    },
                    true,
                ) => self
                    .undeformed_position(body, marker, frame.as_deref())
                    .map_or(0.0, |p| p[component.index()]),
                _ => 0.0,
            })
            .collect()
    }
}

/// Whether a joint has the single coordinate a driver or a JointCoordinate sensor names:
/// a revolute's angle or a prismatic's slide.
fn has_one_coordinate(kind: &JointKind) -> bool {
    matches!(
        kind,
        JointKind::Revolute { .. } | JointKind::Prismatic { .. }
    )
}

/// Parse `PATH=VALUE`.
pub fn parse_set(arg: &str) -> Result<(String, String), ModelError> {
    match arg.split_once('=') {
        Some((p, v)) if !p.is_empty() => Ok((p.trim().to_string(), v.trim().to_string())),
        _ => Err(ModelError::Set {
            path: arg.to_string(),
            message: "expected PATH=VALUE".into(),
        }),
    }
}

/// Whether a list item is an enum variant with fields, serialised `{"Variant": {"name": …}}`
/// (a force, a constraint).
fn is_named_variant(it: &Value) -> bool {
    matches!(it, Value::Object(map) if map.len() == 1
        && !map.contains_key("name")
        && map.values().all(|v| v.get("name").is_some()))
}

/// The `name` of a list item, looked for inside a named variant too.
fn item_name(it: &Value) -> Option<&str> {
    let fields = match it {
        Value::Object(map) if is_named_variant(it) => map.values().next()?,
        _ => it,
    };
    fields.get("name").and_then(|n| n.as_str())
}

/// Whether `map` is a named variant, `{"Variant": {"name": …, …}}`, and `part` one of its
/// fields rather than the variant's name: the path then continues in the fields (so that
/// `constraints.rod.length` reaches the `length` of `Distance(name: "rod", …)`, as
/// `constraints.rod.Distance.length` does).
fn enters_variant(map: &serde_json::Map<String, Value>, part: &str) -> bool {
    map.len() == 1
        && !map.contains_key(part)
        && map
            .values()
            .all(|v| v.is_object() && v.get("name").is_some())
}

fn set_path(tree: &mut Value, path: &str, value: &str) -> Result<(), ModelError> {
    let node = node_at(tree, path)?;
    *node = replacement(node, value).map_err(|m| ModelError::Set {
        path: path.to_string(),
        message: m,
    })?;
    Ok(())
}

impl Scene {
    /// The number at `path` (a `--set` path, e.g. `solver.step`), when it is a real number
    /// of the scene (not an integer count, a flag or a name): what an FMU offers as a
    /// parameter (`flexmbd fmu --parameter`).
    pub fn real_at(&self, path: &str) -> Result<f64, ModelError> {
        let mut tree = serde_json::to_value(self).map_err(|e| ModelError::Set {
            path: path.to_string(),
            message: e.to_string(),
        })?;
        let node = node_at(&mut tree, path)?;
        match node {
            Value::Number(x) if x.is_f64() => Ok(x.as_f64().unwrap_or(f64::NAN)),
            other => Err(ModelError::Set {
                path: path.to_string(),
                message: format!("`{other}` is not a real number"),
            }),
        }
    }
}

/// The node of `tree` at `path` (the `--set` rules: named list items, named variants'
/// fields with or without the variant's name).
fn node_at<'a>(tree: &'a mut Value, path: &str) -> Result<&'a mut Value, ModelError> {
    let err = |m: String| ModelError::Set {
        path: path.to_string(),
        message: m,
    };
    let mut node = tree;
    let parts: Vec<&str> = path.split('.').collect();
    for (i, part) in parts.iter().enumerate() {
        let here = parts[..i].join(".");
        node = match node {
            Value::Object(map) => {
                // A named variant's fields are reached with or without the variant's name.
                let map = if enters_variant(map, part) {
                    match map.values_mut().next() {
                        Some(Value::Object(fields)) => fields,
                        _ => unreachable!("a named variant holds its fields"),
                    }
                } else {
                    map
                };
                let keys: Vec<String> = map.keys().cloned().collect();
                map.get_mut(*part).ok_or_else(|| {
                    err(format!(
                        "`{part}` is not a field of `{}` (fields: {})",
                        if here.is_empty() { "scene" } else { &here },
                        keys.join(", ")
                    ))
                })?
            }
            Value::Array(items) => {
                let names: Vec<String> = items
                    .iter()
                    .filter_map(|it| item_name(it).map(String::from))
                    .collect();
                if let Some(pos) = items.iter().position(|it| item_name(it) == Some(part)) {
                    &mut items[pos]
                } else if let Ok(k) = part.parse::<usize>() {
                    let n = items.len();
                    items.get_mut(k).ok_or_else(|| {
                        err(format!("index {k} out of range ({n} items in `{here}`)"))
                    })?
                } else {
                    return Err(err(format!(
                        "`{here}` has no item named `{part}` (names: {})",
                        names.join(", ")
                    )));
                }
            }
            _ => {
                return Err(err(format!(
                    "`{here}` is a scalar; `{part}` cannot be selected in it"
                )));
            }
        };
    }
    Ok(node)
}

/// The value that replaces `node` for the text `value`, of the node's type (the reason when it
/// cannot be one).
fn replacement(node: &Value, value: &str) -> Result<Value, String> {
    Ok(match node {
        Value::Bool(_) => Value::Bool(
            value
                .parse()
                .map_err(|_| format!("`{value}` is not true or false"))?,
        ),
        Value::Number(_) => {
            let x: f64 = value
                .parse()
                .map_err(|_| format!("`{value}` is not a number"))?;
            if value.contains(['.', 'e', 'E']) || x.fract() != 0.0 || x < 0.0 {
                serde_json::Number::from_f64(x)
                    .map(Value::Number)
                    .ok_or_else(|| format!("`{value}` is not finite"))?
            } else {
                Value::Number((x as u64).into())
            }
        }
        Value::String(_) => Value::String(value.to_string()),
        Value::Null => {
            // An omitted optional field: take a number (written as an integer, an integer,
            // so that an optional count takes it; a float field takes it too), a bool, or a
            // string.
            if let Ok(x) = value.parse::<f64>() {
                if !value.contains(['.', 'e', 'E']) && x.fract() == 0.0 && x >= 0.0 {
                    Value::Number((x as u64).into())
                } else {
                    serde_json::Number::from_f64(x)
                        .map(Value::Number)
                        .ok_or_else(|| format!("`{value}` is not finite"))?
                }
            } else if let Ok(b) = value.parse::<bool>() {
                Value::Bool(b)
            } else {
                Value::String(value.to_string())
            }
        }
        Value::Object(_) | Value::Array(_) => {
            // A structure can be replaced by a unit variant of its enum (`damper=Zero`), which
            // serialises as its name; whether the enum has it is checked on deserialising.
            let variant = value.starts_with(|c: char| c.is_ascii_uppercase())
                && value.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
            if !variant {
                return Err(
                    "this path names a structure, not a scalar; extend the path to a field, or give a unit variant such as Zero"
                        .into(),
                );
            }
            Value::String(value.to_string())
        }
    })
}

/// Dimension check used by formulations: the DOFs a planar model may use.
pub fn planar_dof(d: Dof) -> bool {
    matches!(d, Dof::Ux | Dof::Uy | Dof::Rz)
}
