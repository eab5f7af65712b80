//! What `pickplace robot srdf` does with a URDF, on arbitrary text (lossy UTF-8): the model
//! (mesh paths resolve against a directory that does not exist), the setup assistant's
//! starting SRDF (`pickplace_robot::assistant::starting_srdf`, with one sampled
//! configuration, the fewest the API allows, so an input costs milliseconds), and its XML
//! (`StarterSrdf::to_xml`). The XML written must parse back (`Srdf::from_xml_str`) to the same
//! SRDF, and resolve against the model it was made from (`Semantics::resolve`) with nothing
//! left out (the resolver is lenient: it leaves out what names unknown things, with a
//! warning), as the CLI demands before writing the file.
#![no_main]

use libfuzzer_sys::fuzz_target;
use pickplace_robot::assistant::{StarterOptions, starting_srdf};
use pickplace_robot::collision::AcmOptions;
use pickplace_robot::{LoadOptions, RobotModel, Semantics, Srdf, SrdfWarning};
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let Ok(model) = RobotModel::from_urdf_str(
        &text,
        Path::new("/nonexistent-fuzz-dir"),
        &LoadOptions::default(),
    ) else {
        return;
    };
    let options = StarterOptions {
        acm: AcmOptions {
            samples: 1,
            seed: 0,
            ..AcmOptions::default()
        },
    };
    let Ok(starter) = starting_srdf(&model, &options) else {
        return;
    };
    let xml = starter.to_xml(0);
    let back = Srdf::from_xml_str(&xml)
        .unwrap_or_else(|e| panic!("the written SRDF does not parse: {e}\n{xml}"));
    assert_eq!(
        back, starter.srdf,
        "the SRDF changed on a write and read\n{xml}"
    );
    match Semantics::resolve(&model, &back, Path::new("fuzz.srdf")) {
        Err(e) => panic!("the written SRDF does not resolve against its model: {e}\n{xml}"),
        Ok(semantics) => {
            if let Some(w) = semantics
                .warnings()
                .iter()
                .find(|w| matches!(w, SrdfWarning::LeftOut { .. }))
            {
                panic!("the written SRDF names what its model lacks: {w}\n{xml}");
            }
        }
    }
});
