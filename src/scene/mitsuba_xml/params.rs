//! Typed access to a plugin's parameters. Each read marks the parameter used; [`Plugin::finish`]
//! then makes any parameter or nested plugin the loader did not read an error that names it and
//! lists what the plugin takes, so nothing in a file is silently dropped.

use super::parse::{At, Child, Plugin, Property, Value};
use super::spectrum::spectrum_to_rgb;
use crate::scene::error::SceneError;
use glam::{DMat4, DVec3};
use std::rc::Rc;

/// A colour parameter: a constant, or a nested texture plugin.
#[derive(Clone, Debug)]
pub enum ColorParam {
    Constant([f64; 3]),
    Texture(Rc<Plugin>, At),
}

impl Plugin {
    /// "bsdf 'diffuse'" (with its id, if any), for messages.
    pub fn what(&self) -> String {
        match &self.id {
            Some(id) => format!("{} '{}' (id '{id}')", self.class, self.kind),
            None => format!("{} '{}'", self.class, self.kind),
        }
    }

    /// An error about this plugin, at its line.
    pub fn error(&self, message: impl Into<String>) -> SceneError {
        self.error_at(&self.at, message)
    }

    pub fn error_at(&self, at: &At, message: impl Into<String>) -> SceneError {
        SceneError::Mitsuba {
            at: at.location(),
            plugin: self.what(),
            message: message.into(),
        }
    }

    fn ask(&self, name: &str) {
        let mut asked = self.asked.borrow_mut();
        if !asked.iter().any(|a| a == name) {
            asked.push(name.to_string());
        }
    }

    /// The property `name`, marked used.
    pub fn property(&self, name: &str) -> Option<&Property> {
        self.ask(name);
        let p = self.properties.iter().find(|p| p.name == name)?;
        p.used.set(true);
        Some(p)
    }

    /// Whether the plugin has a property or named child `name` (without using it).
    pub fn has(&self, name: &str) -> bool {
        self.properties.iter().any(|p| p.name == name)
            || self
                .children
                .iter()
                .any(|c| c.name.as_deref() == Some(name))
    }

    fn wrong_type(&self, p: &Property, expected: &str) -> SceneError {
        self.error_at(
            &p.at,
            format!(
                "parameter '{}' is a <{}>; it must be {expected}",
                p.name,
                p.value.tag()
            ),
        )
    }

    pub fn float(&self, name: &str) -> Result<Option<f64>, SceneError> {
        match self.property(name) {
            None => Ok(None),
            Some(p) => match p.value {
                Value::Float(v) => Ok(Some(v)),
                Value::Integer(v) => Ok(Some(v as f64)),
                _ => Err(self.wrong_type(p, "a <float>")),
            },
        }
    }

    pub fn float_or(&self, name: &str, default: f64) -> Result<f64, SceneError> {
        Ok(self.float(name)?.unwrap_or(default))
    }

    pub fn integer(&self, name: &str) -> Result<Option<i64>, SceneError> {
        match self.property(name) {
            None => Ok(None),
            Some(p) => match p.value {
                Value::Integer(v) => Ok(Some(v)),
                _ => Err(self.wrong_type(p, "an <integer>")),
            },
        }
    }

    pub fn string(&self, name: &str) -> Result<Option<(String, At)>, SceneError> {
        match self.property(name) {
            None => Ok(None),
            Some(p) => match &p.value {
                Value::String(v) => Ok(Some((v.clone(), p.at.clone()))),
                _ => Err(self.wrong_type(p, "a <string>")),
            },
        }
    }

    pub fn boolean(&self, name: &str) -> Result<Option<bool>, SceneError> {
        match self.property(name) {
            None => Ok(None),
            Some(p) => match p.value {
                Value::Boolean(v) => Ok(Some(v)),
                _ => Err(self.wrong_type(p, "a <boolean>")),
            },
        }
    }

    pub fn boolean_or(&self, name: &str, default: bool) -> Result<bool, SceneError> {
        Ok(self.boolean(name)?.unwrap_or(default))
    }

    /// A `<point>` (or `<vector>`, which Mitsuba also reads where a point is asked).
    pub fn point(&self, name: &str) -> Result<Option<DVec3>, SceneError> {
        match self.property(name) {
            None => Ok(None),
            Some(p) => match p.value {
                Value::Point(v) | Value::Vector(v) => Ok(Some(v)),
                _ => Err(self.wrong_type(p, "a <point>")),
            },
        }
    }

    pub fn vector(&self, name: &str) -> Result<Option<DVec3>, SceneError> {
        self.point(name)
    }

    pub fn transform(&self, name: &str) -> Result<Option<(DMat4, At)>, SceneError> {
        match self.property(name) {
            None => Ok(None),
            Some(p) => match p.value {
                Value::Transform(m, _) => Ok(Some((m, p.at.clone()))),
                _ => Err(self.wrong_type(p, "a <transform>")),
            },
        }
    }

    /// A transform's lookat (origin, target, up) as written, when it ends in one (see
    /// [`Value::Transform`]).
    pub fn lookat(&self, name: &str) -> Option<[DVec3; 3]> {
        match self.property(name)?.value {
            Value::Transform(_, lookat) => lookat,
            _ => None,
        }
    }

    /// A colour: `<rgb>`, `<spectrum>` (converted as Mitsuba's RGB variants do, see
    /// spectrum.rs), `<float>` (a grey), or a nested `<texture name="...">`.
    pub fn color(&self, name: &str) -> Result<Option<ColorParam>, SceneError> {
        let in_emitter = self.class == "emitter";
        if let Some(p) = self.property(name) {
            return match &p.value {
                Value::Rgb(c) => Ok(Some(ColorParam::Constant(*c))),
                Value::Spectrum(s) => {
                    Ok(Some(ColorParam::Constant(spectrum_to_rgb(s, in_emitter))))
                }
                Value::Float(v) => Ok(Some(ColorParam::Constant([*v; 3]))),
                _ => Err(self.wrong_type(p, "an <rgb>, <spectrum>, <float> or <texture>")),
            };
        }
        match self.named_child(name) {
            Some(c) if c.plugin.class == "texture" => {
                Ok(Some(ColorParam::Texture(c.plugin.clone(), c.at.clone())))
            }
            Some(c) => Err(self.error_at(
                &c.at,
                format!(
                    "parameter '{name}' is a {}; it must be a colour or a <texture>",
                    c.plugin.what()
                ),
            )),
            None => Ok(None),
        }
    }

    /// A colour that must be a constant (no texture), or `default`.
    pub fn constant_color(&self, name: &str, default: [f64; 3]) -> Result<[f64; 3], SceneError> {
        match self.color(name)? {
            None => Ok(default),
            Some(ColorParam::Constant(c)) => Ok(c),
            Some(ColorParam::Texture(t, at)) => Err(self.error_at(
                &at,
                format!(
                    "parameter '{name}': a {} here is not supported, only a constant colour",
                    t.what()
                ),
            )),
        }
    }

    /// The nested plugin with `name="..."`, marked used.
    pub fn named_child(&self, name: &str) -> Option<&Child> {
        self.ask(name);
        let c = self
            .children
            .iter()
            .find(|c| c.name.as_deref() == Some(name))?;
        c.used.set(true);
        Some(c)
    }

    /// The nested plugins of a class (`bsdf`, `emitter`, ...), in order, marked used.
    pub fn children_of(&self, class: &str) -> Vec<&Child> {
        self.ask(&format!("<{class}>"));
        self.children
            .iter()
            .filter(|c| c.plugin.class == class)
            .inspect(|c| c.used.set(true))
            .collect()
    }

    /// At most one nested plugin of a class.
    pub fn child_of(&self, class: &str) -> Result<Option<&Child>, SceneError> {
        let list = self.children_of(class);
        match list[..] {
            [] => Ok(None),
            [c] => Ok(Some(c)),
            [_, second, ..] => Err(self.error_at(
                &second.at,
                format!("has {} nested <{class}> plugins; it takes one", list.len()),
            )),
        }
    }

    /// Marks a parameter read that the loader accepts without effect on passgraph's image (each
    /// caller says why), so that it is not reported as unknown.
    pub fn accept(&self, name: &str) {
        let _ = self.property(name);
    }

    /// An error for the first parameter or nested plugin that nothing read.
    pub fn finish(&self) -> Result<(), SceneError> {
        let takes = || {
            let asked = self.asked.borrow();
            if asked.is_empty() {
                "no parameters".to_string()
            } else {
                asked.join(", ")
            }
        };
        if let Some(p) = self.properties.iter().find(|p| !p.used.get()) {
            return Err(self.error_at(
                &p.at,
                format!(
                    "unknown or unsupported parameter '{}' (<{}>); supported: {}",
                    p.name,
                    p.value.tag(),
                    takes()
                ),
            ));
        }
        if let Some(c) = self.children.iter().find(|c| !c.used.get()) {
            return Err(self.error_at(
                &c.at,
                format!(
                    "a nested {}{} is not supported here; supported: {}",
                    c.plugin.what(),
                    c.name
                        .as_ref()
                        .map_or(String::new(), |n| format!(" named '{n}'")),
                    takes()
                ),
            ));
        }
        Ok(())
    }
}
