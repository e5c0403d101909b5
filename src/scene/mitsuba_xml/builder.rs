//! What the loader collects while it walks the plugins: triangles, materials, textures (each
//! image loaded once), lights, the environment and warnings. The plugin readers (bsdf.rs,
//! emitters.rs, textures.rs) add to it; build.rs walks the tree and makes the scene of it.

use super::parse::{At, resolve_file};
use crate::material::Material;
use crate::scene::emitters::AnalyticLight;
use crate::scene::environment::Environment;
use crate::scene::mesh::MeshTriangle;
use crate::scene::texture::{Encoding, Filter, Texture, Wrap};
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};

/// What the loader collects while it walks the plugins.
pub struct Builder {
    pub(super) search: Vec<PathBuf>,
    pub(super) triangles: Vec<MeshTriangle>,
    pub(super) materials: Vec<Material>,
    pub(super) material_names: Vec<String>,
    pub(super) textures: Vec<Texture>,
    texture_index: HashMap<(PathBuf, Encoding, Filter, Wrap), u32>,
    pub lights: Vec<AnalyticLight>,
    pub environment: Option<Environment>,
    pub(super) warnings: Vec<String>,
    /// Material `front` seen from behind is material `back` (`Mesh::back_materials`).
    pub(super) back_materials: BTreeMap<u32, u32>,
}

impl Builder {
    pub fn new(search: Vec<PathBuf>) -> Builder {
        Builder {
            search,
            triangles: Vec::new(),
            materials: Vec::new(),
            material_names: Vec::new(),
            textures: Vec::new(),
            texture_index: HashMap::new(),
            lights: Vec::new(),
            environment: None,
            warnings: Vec::new(),
            back_materials: BTreeMap::new(),
        }
    }

    /// The image of texture `index`.
    pub fn texture_image(&self, index: u32) -> &Texture {
        &self.textures[index as usize]
    }

    /// A file a plugin names (see [`resolve_file`]).
    pub fn resolve(&self, name: &str, at: &At) -> Option<PathBuf> {
        resolve_file(&self.search, name, at)
    }

    /// The index of an image in the scene's textures, loaded once per (file, encoding,
    /// lookup).
    pub fn texture(
        &mut self,
        path: &Path,
        encoding: Encoding,
        filter: Filter,
        wrap: Wrap,
    ) -> Result<u32, String> {
        let key = (path.to_path_buf(), encoding, filter, wrap);
        if let Some(&i) = self.texture_index.get(&key) {
            return Ok(i);
        }
        let mut t = load_texture(path, encoding)?;
        t.filter = filter;
        t.wrap = wrap;
        let i = self.add_texture(t);
        self.texture_index.insert(key, i);
        Ok(i)
    }

    /// Adds a texture made by the loader (a checkerboard's).
    pub fn add_texture(&mut self, t: Texture) -> u32 {
        self.textures.push(t);
        (self.textures.len() - 1) as u32
    }
}

/// An image file as a texture, the OS's error code left out of the message.
fn load_texture(path: &Path, encoding: Encoding) -> Result<Texture, String> {
    Texture::load(path, encoding).map_err(|message| match message.find(" (os error") {
        Some(at) => message[..at].to_string(),
        None => message,
    })
}
