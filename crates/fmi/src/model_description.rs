//! `modelDescription.xml` of the FMU of a scene (FMI 3.0, co-simulation): the variables
//! of [`crate::variables`], their units, the default experiment (the scene's duration and
//! output interval) and the capabilities — fixed internal step h, variable communication
//! steps (whole numbers of h), get, set and serialisation of the FMU state.

use std::fmt::Write as _;

use flexmbd::model::{Scene, Solver};

use crate::variables::{TIME, Variables};

/// The units the FMU's variables may name, in SI base units (kg, m, s, rad).
const UNITS: [(&str, &str); 7] = [
    ("s", r#"s="1""#),
    ("m", r#"m="1""#),
    ("m/s", r#"m="1" s="-1""#),
    ("rad", r#"rad="1""#),
    ("N", r#"kg="1" m="1" s="-2""#),
    ("N.m", r#"kg="1" m="2" s="-2""#),
    ("J", r#"kg="1" m="2" s="-2""#),
];

/// `text` with the five XML special characters escaped, for an attribute value.
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            '\n' | '\r' | '\t' => out.push(' '),
            c => out.push(c),
        }
    }
    out
}

/// The FMI 3.0 model description of the FMU `identifier` of `scene`, whose variables are
/// `variables` and whose instantiation token is `token`.
pub fn fmi3(scene: &Scene, variables: &Variables, identifier: &str, token: &str) -> String {
    let s = &scene.solver;
    let mut x = String::new();
    let _ = writeln!(x, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        x,
        r#"<fmiModelDescription fmiVersion="3.0" modelName="{}" description="{}" instantiationToken="{}" generationTool="flexmbd {}">"#,
        escape(&scene.name),
        escape(&scene.description),
        escape(token),
        env!("CARGO_PKG_VERSION"),
    );
    let _ = writeln!(
        x,
        r#"  <CoSimulation modelIdentifier="{identifier}" canHandleVariableCommunicationStepSize="true" fixedInternalStepSize="{}" canGetAndSetFMUState="true" canSerializeFMUState="true" canBeInstantiatedOnlyOncePerProcess="false"/>"#,
        s.step
    );
    units_categories_experiment(&mut x, variables, s, Some("s"));
    let _ = writeln!(x, "  <ModelVariables>");
    let _ = writeln!(
        x,
        r#"    <Float64 name="time" valueReference="{TIME}" causality="independent" variability="continuous" unit="s" description="simulated time"/>"#
    );
    for (k, v) in variables.inputs.iter().enumerate() {
        let _ = writeln!(
            x,
            r#"    <Float64 name="{}" valueReference="{}" causality="input" variability="continuous" start="{}"{} description="{}"/>"#,
            escape(&v.name),
            variables.input_reference(k),
            v.start,
            unit_attribute(v.unit),
            escape(&v.description),
        );
    }
    for (k, v) in variables.outputs.iter().enumerate() {
        let _ = writeln!(
            x,
            r#"    <Float64 name="{}" valueReference="{}" causality="output" variability="continuous"{} description="sensor {}"/>"#,
            escape(&v.name),
            variables.output_reference(k),
            unit_attribute(v.unit),
            escape(&v.name),
        );
    }
    for (k, p) in variables.parameters.iter().enumerate() {
        let _ = writeln!(
            x,
            r#"    <Float64 name="{}" valueReference="{}" causality="parameter" variability="fixed" initial="exact" start="{}" description="the scene's {}, set before the start"/>"#,
            escape(&p.name),
            variables.parameter_reference(k),
            p.start,
            escape(&p.name),
        );
    }
    let _ = writeln!(x, "  </ModelVariables>");
    let _ = writeln!(x, "  <ModelStructure>");
    for k in 0..variables.outputs.len() {
        let _ = writeln!(
            x,
            r#"    <Output valueReference="{}"/>"#,
            variables.output_reference(k)
        );
    }
    for k in 0..variables.outputs.len() {
        let _ = writeln!(
            x,
            r#"    <InitialUnknown valueReference="{}"/>"#,
            variables.output_reference(k)
        );
    }
    let _ = writeln!(x, "  </ModelStructure>");
    let _ = writeln!(x, "</fmiModelDescription>");
    x
}

/// The unit definitions of the units the variables use (and `extra`, the time's), the log
/// categories and the default experiment (the scene's duration and output interval).
fn units_categories_experiment(
    x: &mut String,
    variables: &Variables,
    s: &Solver,
    extra: Option<&'static str>,
) {
    let used: Vec<&str> = extra
        .into_iter()
        .chain(variables.inputs.iter().filter_map(|v| v.unit))
        .chain(variables.outputs.iter().filter_map(|v| v.unit))
        .collect();
    let units: Vec<_> = UNITS.iter().filter(|(u, _)| used.contains(u)).collect();
    if !units.is_empty() {
        let _ = writeln!(x, "  <UnitDefinitions>");
        for (name, base) in units {
            let _ = writeln!(x, r#"    <Unit name="{name}"><BaseUnit {base}/></Unit>"#);
        }
        let _ = writeln!(x, "  </UnitDefinitions>");
    }
    let _ = writeln!(
        x,
        r#"  <LogCategories>
    <Category name="logStatusError" description="a refused call or a failed step"/>
    <Category name="logStatusFatal" description="an internal error"/>
  </LogCategories>"#
    );
    let _ = writeln!(
        x,
        r#"  <DefaultExperiment startTime="0" stopTime="{}" stepSize="{}"/>"#,
        s.duration,
        s.output_interval.unwrap_or(s.step)
    );
}

fn unit_attribute(unit: Option<&str>) -> String {
    unit.map_or_else(String::new, |u| format!(r#" unit="{u}""#))
}

/// The FMI 2.0 model description of the same FMU: the same value references (no `time`
/// variable: FMI 2.0 has none), `ScalarVariable`s of type `Real`, the model structure by
/// 1-based indices into the variable list, and the GUID `token`.
pub fn fmi2(scene: &Scene, variables: &Variables, identifier: &str, token: &str) -> String {
    let s = &scene.solver;
    let mut x = String::new();
    let _ = writeln!(x, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        x,
        r#"<fmiModelDescription fmiVersion="2.0" modelName="{}" description="{}" guid="{}" generationTool="flexmbd {}" variableNamingConvention="flat" numberOfEventIndicators="0">"#,
        escape(&scene.name),
        escape(&scene.description),
        escape(token),
        env!("CARGO_PKG_VERSION"),
    );
    let _ = writeln!(
        x,
        r#"  <CoSimulation modelIdentifier="{identifier}" canHandleVariableCommunicationStepSize="true" canGetAndSetFMUstate="true" canSerializeFMUstate="true" canNotUseMemoryManagementFunctions="true" canBeInstantiatedOnlyOncePerProcess="false"/>"#,
    );
    units_categories_experiment(&mut x, variables, s, None);
    let _ = writeln!(x, "  <ModelVariables>");
    for (k, v) in variables.inputs.iter().enumerate() {
        let _ = writeln!(
            x,
            r#"    <ScalarVariable name="{}" valueReference="{}" causality="input" variability="continuous" description="{}"><Real start="{}"{}/></ScalarVariable>"#,
            escape(&v.name),
            variables.input_reference(k),
            escape(&v.description),
            v.start,
            unit_attribute(v.unit),
        );
    }
    for (k, v) in variables.outputs.iter().enumerate() {
        let _ = writeln!(
            x,
            r#"    <ScalarVariable name="{}" valueReference="{}" causality="output" variability="continuous" initial="calculated" description="sensor {}"><Real{}/></ScalarVariable>"#,
            escape(&v.name),
            variables.output_reference(k),
            escape(&v.name),
            unit_attribute(v.unit),
        );
    }
    for (k, p) in variables.parameters.iter().enumerate() {
        let _ = writeln!(
            x,
            r#"    <ScalarVariable name="{}" valueReference="{}" causality="parameter" variability="fixed" initial="exact" description="the scene's {}, set before the start"><Real start="{}"/></ScalarVariable>"#,
            escape(&p.name),
            variables.parameter_reference(k),
            escape(&p.name),
            p.start,
        );
    }
    let _ = writeln!(x, "  </ModelVariables>");
    let _ = writeln!(x, "  <ModelStructure>");
    let first_output = variables.inputs.len() + 1;
    let n = variables.outputs.len();
    if n > 0 {
        let _ = writeln!(x, "    <Outputs>");
        for k in 0..n {
            let _ = writeln!(x, r#"      <Unknown index="{}"/>"#, first_output + k);
        }
        let _ = writeln!(x, "    </Outputs>");
        let _ = writeln!(x, "    <InitialUnknowns>");
        for k in 0..n {
            let _ = writeln!(x, r#"      <Unknown index="{}"/>"#, first_output + k);
        }
        let _ = writeln!(x, "    </InitialUnknowns>");
    }
    let _ = writeln!(x, "  </ModelStructure>");
    let _ = writeln!(x, "</fmiModelDescription>");
    x
}
