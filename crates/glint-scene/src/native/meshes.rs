//! `mesh "name" { file "bunny.obj" }` (a definition, read once) and
//! `mesh_instance "name" { material "m" transforms… }` (a placement of it).

use glint_core::desc::{NodeDesc, NodeKind, ShapeDesc};

use super::args::{self, Result, Seen};
use super::builder::{Builder, Source};
use super::objects::{TRANSFORMS, transform_op};
use super::tree::Node;

impl Builder {
    /// `mesh "name" { file "…" }`: reads the mesh file now; every placement in it is
    /// baked into one mesh, stored once however often it is instanced.
    pub fn mesh_definition(&mut self, src: &Source, node: &Node) -> Result<()> {
        let (name, pos) = args::string(src, node, "a mesh name")?;
        let mut file = None;
        let mut seen = Seen::default();
        for prop in node.children() {
            seen.once(src, prop, "mesh")?;
            match prop.name.as_str() {
                "file" => {
                    args::no_block(src, prop)?;
                    file = Some(args::string(src, prop, "a file name")?.0);
                }
                _ => return Err(args::unknown(src, prop, "property", "in 'mesh'", &["file"])),
            }
        }
        let Some(file) = file else {
            return Err(src.invalid(node.pos(), "a mesh needs its file, as in `mesh \"bunny\" { file \"bunny.obj\" }`"));
        };
        self.mesh_names.insert(src, pos, "mesh", &name, self.desc.meshes.len())?;
        let path = src.dir.join(&file);
        // The file's own errors name the file and line they are about.
        let import = crate::mesh::load_mesh(&path)?;
        self.desc.meshes.push(crate::mesh::merged(&import, &name, &path.display().to_string()));
        Ok(())
    }

    /// `mesh_instance "name" { material "m" transforms… }`.
    pub fn mesh_instance(&mut self, src: &Source, node: &Node) -> Result<NodeDesc> {
        let (name, pos) = args::string(src, node, "a mesh name")?;
        let index = self.mesh_names.lookup(src, pos, "mesh", &name)?;
        let mut transform = Vec::new();
        let mut material = None;
        let mut seen = Seen::default();
        for prop in node.children() {
            if let Some(op) = transform_op(src, prop)? {
                transform.push(op);
                continue;
            }
            if prop.name != "material" {
                let mut allowed = vec!["material"];
                allowed.extend(TRANSFORMS);
                return Err(args::unknown(src, prop, "property", "in 'mesh_instance'", &allowed));
            }
            seen.once(src, prop, "mesh_instance")?;
            args::no_block(src, prop)?;
            let (material_name, pos) = args::string(src, prop, "a material name")?;
            material = Some(self.materials.lookup(src, pos, "material", &material_name)?);
        }
        let material = match material {
            Some(index) => index,
            None => self.default_material(src, node.pos())?,
        };
        self.count_nodes(src, node.pos(), 1)?;
        Ok(NodeDesc {
            transform,
            kind: NodeKind::Shape { shape: ShapeDesc::Mesh { index }, material },
            origin: src.origin(node.pos()),
        })
    }
}
