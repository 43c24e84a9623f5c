//! Meshes out as binary little-endian PLY files, which glint's PLY reader reads back
//! exactly (32-bit floats, 32-bit indices): how `glint convert` saves meshes that were
//! written inline in a scene (pbrt's `trianglemesh`, tessellated cylinders), since a
//! `.glint` file can only name mesh files.

use glint_core::desc::MeshDesc;

/// The PLY bytes of `mesh`: positions, and normals and uvs when it has them.
pub fn ply_bytes(mesh: &MeshDesc) -> Vec<u8> {
    let normals = mesh.normals.len() == mesh.positions.len() && !mesh.normals.is_empty();
    let uvs = mesh.uvs.len() == mesh.positions.len() && !mesh.uvs.is_empty();
    let mut header = format!(
        "ply\nformat binary_little_endian 1.0\ncomment written by glint\nelement vertex {}\n\
         property float x\nproperty float y\nproperty float z\n",
        mesh.positions.len()
    );
    if normals {
        header.push_str("property float nx\nproperty float ny\nproperty float nz\n");
    }
    if uvs {
        header.push_str("property float u\nproperty float v\n");
    }
    header.push_str(&format!(
        "element face {}\nproperty list uchar uint vertex_indices\nend_header\n",
        mesh.indices.len() / 3
    ));
    let mut out = header.into_bytes();
    for (i, p) in mesh.positions.iter().enumerate() {
        let mut floats = p.to_array().to_vec();
        if normals {
            floats.extend(mesh.normals[i].to_array());
        }
        if uvs {
            floats.extend(mesh.uvs[i].to_array());
        }
        for f in floats {
            out.extend(f.to_le_bytes());
        }
    }
    for tri in mesh.indices.chunks_exact(3) {
        out.push(3);
        for &i in tri {
            out.extend(i.to_le_bytes());
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use glam::{Vec2, Vec3};

    use super::*;

    #[test]
    fn a_written_mesh_reads_back_the_same() {
        let mesh = MeshDesc {
            positions: vec![Vec3::ZERO, Vec3::new(1.5, -0.25, 3.0), Vec3::Y],
            normals: vec![Vec3::Z; 3],
            uvs: vec![Vec2::ZERO, Vec2::X, Vec2::new(0.25, 0.75)],
            indices: vec![0, 1, 2],
            ..MeshDesc::default()
        };
        let import = crate::mesh::parse_mesh(std::path::Path::new("m.ply"), ply_bytes(&mesh)).unwrap();
        let back = &import.meshes[0];
        assert_eq!(
            (&back.positions, &back.normals, &back.uvs, &back.indices),
            (&mesh.positions, &mesh.normals, &mesh.uvs, &mesh.indices)
        );
    }
}
