//! The FMU's `modelDescription.xml` (FMI 2.0, co-simulation only): the model's name and
//! GUID, the `CoSimulation` capabilities of the slave library (`fmu/`), the units of its
//! variables, the default experiment, one `ScalarVariable` per input and output, and the
//! `ModelStructure` that lists the outputs. Written from the FMI 2.0 standard's schema
//! (`fmi2ModelDescription.xsd`: the order of the elements, the attributes each causality
//! may carry).

use super::interface::{Interface, Port};
use super::units::{fmi_unit, FmiUnit};
use crate::model::elements::Units;
use std::fmt::Write;

/// What the description says beside the variables.
pub struct Header<'a> {
    /// `modelName`: the dataset's title (its first line), else the identifier.
    pub model_name: &'a str,
    /// `modelIdentifier`: the library's name in `binaries/`.
    pub model_identifier: &'a str,
    /// The GUID, braces included.
    pub guid: &'a str,
    /// `DefaultExperiment`: the stop time and the step, when known.
    pub stop_time: Option<f64>,
    /// The communication step of `DefaultExperiment`.
    pub step_size: Option<f64>,
    /// The `tolerance` of `DefaultExperiment` (the ERROR the FMU runs with).
    pub tolerance: Option<f64>,
}

/// The XML text of the description of an FMU with `interface`, in the dataset's `units`.
pub fn model_description(header: &Header<'_>, interface: &Interface, units: &Units) -> String {
    let ports: Vec<(&Port, bool)> = interface
        .inputs
        .iter()
        .map(|p| (p, true))
        .chain(interface.outputs.iter().map(|p| (p, false)))
        .collect();
    let port_units: Vec<Option<FmiUnit>> = ports
        .iter()
        .map(|(p, _)| p.dim.and_then(|d| fmi_unit(d, units)))
        .collect();
    let mut x = String::new();
    let _ = writeln!(x, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        x,
        r#"<fmiModelDescription fmiVersion="2.0" modelName="{}" guid="{}" description="{}" generationTool="mbfx {}" variableNamingConvention="flat" numberOfEventIndicators="0">"#,
        escape(header.model_name),
        escape(header.guid),
        escape("an Adams dataset run by mbfx (mbfx fmu)"),
        env!("CARGO_PKG_VERSION"),
    );
    // The slave integrates to each communication point with error control, takes any
    // step size, keeps snapshots (fmi2GetFMUstate), and does not serialize them.
    let _ = writeln!(
        x,
        r#"  <CoSimulation modelIdentifier="{}" canHandleVariableCommunicationStepSize="true" canInterpolateInputs="false" maxOutputDerivativeOrder="0" canBeInstantiatedOnlyOncePerProcess="false" canNotUseMemoryManagementFunctions="true" canGetAndSetFMUstate="true" canSerializeFMUstate="false" providesDirectionalDerivative="false"/>"#,
        escape(header.model_identifier)
    );
    let mut defined: Vec<&FmiUnit> = Vec::new();
    for u in port_units.iter().flatten() {
        if !defined.iter().any(|d| d.name == u.name) {
            defined.push(u);
        }
    }
    if !defined.is_empty() {
        let _ = writeln!(x, "  <UnitDefinitions>");
        for u in defined {
            let mut base = String::new();
            for (symbol, e) in &u.exponents {
                let _ = write!(base, r#" {symbol}="{e}""#);
            }
            if u.factor != 1.0 {
                let _ = write!(base, r#" factor="{}""#, number(u.factor));
            }
            let _ = writeln!(
                x,
                r#"    <Unit name="{}"><BaseUnit{base}/></Unit>"#,
                escape(&u.name)
            );
        }
        let _ = writeln!(x, "  </UnitDefinitions>");
    }
    let _ = writeln!(x, "  <LogCategories>");
    for (name, what) in LOG_CATEGORIES {
        let _ = writeln!(
            x,
            r#"    <Category name="{name}" description="{}"/>"#,
            escape(what)
        );
    }
    let _ = writeln!(x, "  </LogCategories>");
    let mut experiment = String::from(r#" startTime="0""#);
    if let Some(t) = header.stop_time {
        let _ = write!(experiment, r#" stopTime="{}""#, number(t));
    }
    if let Some(t) = header.tolerance {
        let _ = write!(experiment, r#" tolerance="{}""#, number(t));
    }
    if let Some(h) = header.step_size {
        let _ = write!(experiment, r#" stepSize="{}""#, number(h));
    }
    let _ = writeln!(x, "  <DefaultExperiment{experiment}/>");
    let _ = writeln!(x, "  <ModelVariables>");
    for (reference, ((port, input), unit)) in ports.iter().zip(&port_units).enumerate() {
        let causality = if *input { "input" } else { "output" };
        let _ = writeln!(
            x,
            r#"    <ScalarVariable name="{}" valueReference="{reference}" description="VARIABLE/{}" causality="{causality}" variability="continuous">"#,
            escape(&port.name),
            port.variable
        );
        let mut real = String::new();
        if *input {
            let _ = write!(real, r#" start="{}""#, number(port.start));
        }
        if let Some(u) = unit {
            let _ = write!(real, r#" unit="{}""#, escape(&u.name));
        }
        let _ = writeln!(x, "      <Real{real}/>");
        let _ = writeln!(x, "    </ScalarVariable>");
    }
    let _ = writeln!(x, "  </ModelVariables>");
    // Indices are 1-based positions in ModelVariables: the outputs follow the inputs.
    let outputs: Vec<usize> = (1..=ports.len()).skip(interface.inputs.len()).collect();
    let _ = writeln!(x, "  <ModelStructure>");
    for section in ["Outputs", "InitialUnknowns"] {
        let _ = writeln!(x, "    <{section}>");
        for i in &outputs {
            let _ = writeln!(x, r#"      <Unknown index="{i}"/>"#);
        }
        let _ = writeln!(x, "    </{section}>");
    }
    let _ = writeln!(x, "  </ModelStructure>");
    let _ = writeln!(x, "</fmiModelDescription>");
    x
}

/// The log categories the slave library logs under (`fmi2SetDebugLogging`).
pub const LOG_CATEGORIES: [(&str, &str); 3] = [
    ("logStatusError", "calls that fail, with the reason"),
    ("logStatusWarning", "calls that succeed with a warning"),
    ("logAll", "every call, with its arguments"),
];

/// `text` with the five XML special characters escaped, for an attribute value.
fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            // Control characters are not allowed in XML 1.0 text.
            c if c.is_control() => out.push(' '),
            c => out.push(c),
        }
    }
    out
}

/// A number as XML's xs:double reads it back to the same bits (Rust's shortest form).
fn number(x: f64) -> String {
    format!("{x:?}")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::check::units::Dim;

    fn port(name: &str, variable: u32, dim: Option<Dim>) -> Port {
        Port {
            name: name.into(),
            variable,
            start: 0.5,
            dim,
        }
    }

    #[test]
    fn inputs_carry_a_start_outputs_are_listed_in_the_structure_and_units_once() {
        let interface = Interface {
            inputs: vec![port("u", 1, Some(Dim::FORCE))],
            outputs: vec![
                port("y", 2, Some(Dim::LENGTH)),
                port("z", 3, Some(Dim::LENGTH)),
            ],
        };
        let header = Header {
            model_name: "a <plant> & more",
            model_identifier: "plant",
            guid: "{g}",
            stop_time: Some(2.0),
            step_size: None,
            tolerance: None,
        };
        let x = model_description(&header, &interface, &Units::default());
        assert!(
            x.contains(r#"modelName="a &lt;plant&gt; &amp; more""#),
            "{x}"
        );
        assert!(
            x.contains(r#"name="u" valueReference="0" description="VARIABLE/1" causality="input""#),
            "{x}"
        );
        assert!(x.contains(r#"<Real start="0.5" unit="newton"/>"#), "{x}");
        assert!(x.contains(r#"<Real unit="meter"/>"#), "{x}");
        assert_eq!(x.matches(r#"<Unit name="meter">"#).count(), 1, "{x}");
        assert!(x.contains(r#"<Unknown index="2"/>"#) && x.contains(r#"<Unknown index="3"/>"#));
        assert!(!x.contains(r#"<Unknown index="1"/>"#), "{x}");
        assert!(
            x.contains(r#"<DefaultExperiment startTime="0" stopTime="2.0"/>"#),
            "{x}"
        );
    }
}
