//! The contact table as one tagged value per model: `model` omitted is the foundation, each
//! model takes its own fields only (serde names any other), and a table is written back as it
//! was read.

use scene::{ContactSpec, FoundationSpec, LineOfCentresSpec, LinearSpringSpec};
use serde::{Deserialize, Serialize};

/// A table holding one `contact` value, as a clearance joint does.
#[derive(Debug, Deserialize, Serialize)]
struct Holder {
    contact: ContactSpec,
}

fn read(contact: &str) -> Result<ContactSpec, String> {
    toml::from_str::<Holder>(&format!("contact = {contact}\n"))
        .map(|h| h.contact)
        .map_err(|e| e.to_string())
}

fn written(contact: ContactSpec) -> String {
    toml::to_string(&Holder { contact }).expect("serializes")
}

#[test]
fn a_table_without_model_is_the_foundation() {
    assert_eq!(read("{}"), Ok(ContactSpec::default()));
    assert_eq!(
        read("{ cells = 500 }"),
        Ok(ContactSpec::Foundation(FoundationSpec {
            cells: Some(500),
            ..FoundationSpec::default()
        }))
    );
    assert_eq!(
        read("{ model = \"foundation\" }"),
        Ok(ContactSpec::default())
    );
    assert_eq!(ContactSpec::default().name(), "foundation");
}

#[test]
fn each_model_reads_its_own_fields() {
    assert_eq!(
        read("{ model = \"line-of-centres\" }"),
        Ok(ContactSpec::line_of_centres())
    );
    assert_eq!(
        read("{ model = \"linear-spring\", stiffness = 1e9 }"),
        Ok(ContactSpec::LinearSpring(LinearSpringSpec {
            stiffness: 1e9
        }))
    );
    // An integer where a number is expected reads as one, as elsewhere in a scene.
    assert_eq!(
        read("{ model = \"linear-spring\", stiffness = 1000 }"),
        Ok(LinearSpringSpec { stiffness: 1e3 }.into())
    );
}

#[test]
fn another_models_field_or_an_unknown_model_is_refused_by_name() {
    let refused = |contact: &str, words: &[&str]| {
        let e = read(contact).expect_err(contact);
        for w in words {
            assert!(e.contains(w), "{contact}: {e}");
        }
    };
    refused(
        "{ stiffness = 1e9 }",
        &["unknown field `stiffness`", "layer_modulus"],
    );
    refused(
        "{ model = \"line-of-centres\", cells = 500 }",
        &["unknown field `cells`"],
    );
    refused(
        "{ model = \"linear-spring\", stiffness = 1e9, width = 0.1 }",
        &["unknown field `width`", "stiffness"],
    );
    refused(
        "{ model = \"linear-spring\" }",
        &["missing field `stiffness`"],
    );
    refused(
        "{ model = \"winkler\" }",
        &[
            "unknown variant `winkler`",
            "foundation",
            "line-of-centres",
            "linear-spring",
        ],
    );
    refused("{ cells = \"many\" }", &["many"]);
}

/// A table is written as before the tagged value: `model` first, then the fields given, none
/// left at its default; and read back the same.
#[test]
fn a_table_is_written_back_as_it_was_read() {
    let layer = ContactSpec::Foundation(FoundationSpec {
        cells: Some(500),
        reference_speed: Some(0.1),
        ..FoundationSpec::default()
    });
    for (spec, text) in [
        (
            layer,
            "[contact]\nmodel = \"foundation\"\ncells = 500\nreference_speed = 0.1\n",
        ),
        (
            ContactSpec::line_of_centres(),
            "[contact]\nmodel = \"line-of-centres\"\n",
        ),
        (
            LinearSpringSpec { stiffness: 1e9 }.into(),
            "[contact]\nmodel = \"linear-spring\"\nstiffness = 1000000000.0\n",
        ),
    ] {
        assert_eq!(written(spec), text);
        let again: Holder = toml::from_str(text).expect("reads back");
        assert_eq!(again.contact, spec);
    }
    assert_eq!(
        ContactSpec::from(LineOfCentresSpec {}),
        ContactSpec::line_of_centres()
    );
}
