//! Resources and overrides an application provides by name, which passes bind like their own.
//! The compiler knows none of them: the application registers them in a [`ProvidedSet`] and
//! passes it to `compile`, and fills their data from the same registration.

use super::param::ParamType;

/// How a provided resource is bound.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ProvidedKind {
    /// A read-only storage buffer, also bindable as a texel view of its bytes.
    StorageBuffer,
    /// A uniform block the application may update every frame.
    Uniform,
}

/// A resource the application provides.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Provided {
    pub name: String,
    pub kind: ProvidedKind,
    /// What it holds, for messages and listings.
    pub what: String,
    /// The shader variable bound to it when a pass instance's `bind` does not name one: shaders
    /// declare it once (in a file they include) and graphs need not list it.
    pub variable: Option<String>,
}

/// A pipeline-overridable constant the application sets, so shaders can be specialised to its
/// data (e.g. no loop over an empty list).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ProvidedOverride {
    pub name: String,
    pub ty: ParamType,
    pub what: String,
}

/// Everything an application provides to its graphs, in registration order (the order the
/// plan lists provided resources in).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ProvidedSet {
    resources: Vec<Provided>,
    overrides: Vec<ProvidedOverride>,
    /// The WGSL file whose functions read a storage buffer as texels, named in binding errors.
    texel_readers: Option<String>,
}

impl ProvidedSet {
    /// A set that provides nothing: graphs declare every resource they bind.
    pub fn new() -> ProvidedSet {
        ProvidedSet::default()
    }

    /// Registers a resource. A name registered twice is a bug in the application.
    pub fn resource(
        mut self,
        name: impl Into<String>,
        kind: ProvidedKind,
        what: impl Into<String>,
    ) -> ProvidedSet {
        let name = name.into();
        assert!(
            self.get(&name).is_none(),
            "provided resource '{name}' registered twice"
        );
        self.resources.push(Provided {
            name,
            kind,
            what: what.into(),
            variable: None,
        });
        self
    }

    /// Binds the registered resource `resource` to every shader variable named `variable` that
    /// a pass instance leaves out of its `bind` (an instance's own entry still wins). Naming a
    /// resource not registered, or a variable twice, is a bug in the application.
    pub fn bind_by_name(mut self, variable: impl Into<String>, resource: &str) -> ProvidedSet {
        let variable = variable.into();
        assert!(
            self.bound_by_name(&variable).is_none(),
            "shader variable '{variable}' bound by name twice"
        );
        let Some(provided) = self.resources.iter_mut().find(|p| p.name == resource) else {
            panic!("'{resource}' is bound by name but not registered");
        };
        assert!(
            provided.variable.is_none(),
            "provided resource '{resource}' bound by name twice"
        );
        provided.variable = Some(variable);
        self
    }

    /// Registers an override. A name registered twice is a bug in the application.
    pub fn override_constant(
        mut self,
        name: impl Into<String>,
        ty: ParamType,
        what: impl Into<String>,
    ) -> ProvidedSet {
        let name = name.into();
        assert!(
            self.get_override(&name).is_none(),
            "provided override '{name}' registered twice"
        );
        self.overrides.push(ProvidedOverride {
            name,
            ty,
            what: what.into(),
        });
        self
    }

    /// Names the WGSL file whose readers take a storage buffer as texels, for binding errors.
    pub fn texel_readers(mut self, file: impl Into<String>) -> ProvidedSet {
        self.texel_readers = Some(file.into());
        self
    }

    pub fn resources(&self) -> &[Provided] {
        &self.resources
    }

    pub fn overrides(&self) -> &[ProvidedOverride] {
        &self.overrides
    }

    pub fn get(&self, name: &str) -> Option<&Provided> {
        self.resources.iter().find(|p| p.name == name)
    }

    pub fn get_override(&self, name: &str) -> Option<&ProvidedOverride> {
        self.overrides.iter().find(|o| o.name == name)
    }

    /// The resource bound to shader variable `variable` when an instance does not bind it.
    pub fn bound_by_name(&self, variable: &str) -> Option<&Provided> {
        self.resources
            .iter()
            .find(|p| p.variable.as_deref() == Some(variable))
    }

    pub fn texel_reader_file(&self) -> Option<&str> {
        self.texel_readers.as_deref()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_what_was_registered_and_nothing_else() {
        let set = ProvidedSet::new()
            .resource("mesh", ProvidedKind::StorageBuffer, "vertices")
            .override_constant("mesh_count", ParamType::U32, "vertex count");
        assert_eq!(
            set.get("mesh").map(|p| p.kind),
            Some(ProvidedKind::StorageBuffer)
        );
        assert_eq!(
            set.get_override("mesh_count").map(|o| o.ty),
            Some(ParamType::U32)
        );
        assert!(set.get("mesh_count").is_none());
        assert!(set.get_override("mesh").is_none());
    }

    #[test]
    fn a_variable_bound_by_name_finds_its_resource_and_no_other() {
        let set = ProvidedSet::new()
            .resource("scene.mesh", ProvidedKind::StorageBuffer, "vertices")
            .resource("scene.lights", ProvidedKind::StorageBuffer, "lights")
            .bind_by_name("mesh", "scene.mesh");
        assert_eq!(
            set.bound_by_name("mesh").map(|p| p.name.as_str()),
            Some("scene.mesh")
        );
        assert!(set.bound_by_name("lights").is_none());
        assert!(set.bound_by_name("scene.mesh").is_none());
    }

    #[test]
    #[should_panic(expected = "bound by name twice")]
    fn a_variable_bound_to_two_resources_is_a_bug() {
        let _ = ProvidedSet::new()
            .resource("a", ProvidedKind::StorageBuffer, "a")
            .resource("b", ProvidedKind::StorageBuffer, "b")
            .bind_by_name("x", "a")
            .bind_by_name("x", "b");
    }

    #[test]
    #[should_panic(expected = "registered twice")]
    fn a_name_registered_twice_is_a_bug() {
        let _ = ProvidedSet::new()
            .resource("a", ProvidedKind::Uniform, "")
            .resource("a", ProvidedKind::StorageBuffer, "");
    }
}
