//! Scenes shipped as text under a name: what `extends = "<name>"` and a scene given by name
//! refer to. The crate that ships them (the LGRES model, `lgres::scenes::BUILTINS`) hands its
//! list to the loaders (`extends`).

/// A scene shipped as TOML text under a name.
#[derive(Debug, Clone, Copy)]
pub struct Builtin {
    /// Name used on the command line and in `extends`.
    pub name: &'static str,
    /// One-line summary.
    pub summary: &'static str,
    /// The TOML text.
    pub source: &'static str,
}

/// The TOML text of the scene of `builtins` named `name`.
pub fn source(builtins: &[Builtin], name: &str) -> Option<&'static str> {
    builtins.iter().find(|b| b.name == name).map(|b| b.source)
}

/// The comma-separated names of `builtins`, for errors that list them.
pub(crate) fn known_names(builtins: &[Builtin]) -> String {
    builtins
        .iter()
        .map(|b| b.name)
        .collect::<Vec<_>>()
        .join(", ")
}
