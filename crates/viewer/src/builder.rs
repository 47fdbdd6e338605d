//! The buffer and the accessors, meshes and animation channels of a glTF document being
//! written ([`crate::glb`]): every array goes into the one binary buffer, 4-byte aligned,
//! behind a buffer view and an accessor (with the bounds the specification requires of
//! positions and animation inputs).

use gltf_json as json;
use json::validation::{Checked::Valid, USize64};
use nalgebra::Vector3;

use crate::shapes::BodyShape;

/// The buffer being filled and the document that views it.
pub(crate) struct Builder {
    pub(crate) root: json::Root,
    pub(crate) bin: Vec<u8>,
}

impl Builder {
    /// A view of `bytes` appended to the buffer (4-byte aligned).
    pub(crate) fn view(
        &mut self,
        bytes: &[u8],
        target: Option<json::buffer::Target>,
    ) -> json::Index<json::buffer::View> {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        self.root.push(json::buffer::View {
            buffer: json::Index::new(0),
            byte_length: USize64(bytes.len() as u64),
            byte_offset: Some(USize64(offset as u64)),
            byte_stride: None,
            name: None,
            target: target.map(Valid),
            extensions: None,
            extras: None,
        })
    }

    /// An accessor of `values` (f32, `width` per element of type `type_`), with its bounds
    /// when `bounds` (required for positions and animation inputs).
    pub(crate) fn floats(
        &mut self,
        values: &[f32],
        type_: json::accessor::Type,
        width: usize,
        bounds: bool,
        target: Option<json::buffer::Target>,
    ) -> json::Index<json::Accessor> {
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.view(&bytes, target);
        let (min, max) = if bounds {
            let column = |k: usize| values.iter().skip(k).step_by(width).copied();
            let min: Vec<f32> = (0..width)
                .map(|k| column(k).fold(f32::INFINITY, f32::min))
                .collect();
            let max: Vec<f32> = (0..width)
                .map(|k| column(k).fold(f32::NEG_INFINITY, f32::max))
                .collect();
            (Some(serde_json::json!(min)), Some(serde_json::json!(max)))
        } else {
            (None, None)
        };
        self.root.push(json::Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64((values.len() / width) as u64),
            component_type: Valid(json::accessor::GenericComponentType(
                json::accessor::ComponentType::F32,
            )),
            type_: Valid(type_),
            min,
            max,
            name: None,
            normalized: false,
            sparse: None,
            extensions: None,
            extras: None,
        })
    }

    pub(crate) fn vectors(
        &mut self,
        values: &[Vector3<f64>],
        bounds: bool,
    ) -> json::Index<json::Accessor> {
        let flat: Vec<f32> = values
            .iter()
            .flat_map(|v| [v.x as f32, v.y as f32, v.z as f32])
            .collect();
        self.floats(
            &flat,
            json::accessor::Type::Vec3,
            3,
            bounds,
            Some(json::buffer::Target::ArrayBuffer),
        )
    }

    pub(crate) fn indices(&mut self, triangles: &[[u32; 3]]) -> json::Index<json::Accessor> {
        let bytes: Vec<u8> = triangles
            .iter()
            .flatten()
            .flat_map(|i| i.to_le_bytes())
            .collect();
        let view = self.view(&bytes, Some(json::buffer::Target::ElementArrayBuffer));
        self.root.push(json::Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64(3 * triangles.len() as u64),
            component_type: Valid(json::accessor::GenericComponentType(
                json::accessor::ComponentType::U32,
            )),
            type_: Valid(json::accessor::Type::Scalar),
            min: None,
            max: None,
            name: None,
            normalized: false,
            sparse: None,
            extensions: None,
            extras: None,
        })
    }

    /// The mesh of a body (none when it has no triangles), its colour the `k`th.
    pub(crate) fn mesh(
        &mut self,
        shape: &BodyShape,
        [r, g, b]: [f32; 3],
    ) -> Option<json::Index<json::Mesh>> {
        if shape.triangles.is_empty() {
            return None;
        }
        let material = self.root.push(json::Material {
            name: Some(shape.name.clone()),
            double_sided: true,
            pbr_metallic_roughness: json::material::PbrMetallicRoughness {
                base_color_factor: json::material::PbrBaseColorFactor([r, g, b, 1.0]),
                metallic_factor: json::material::StrengthFactor(0.1),
                roughness_factor: json::material::StrengthFactor(0.6),
                ..Default::default()
            },
            ..Default::default()
        });
        let positions = self.vectors(&shape.positions, true);
        let normals = self.vectors(&shape.normals, false);
        let indices = self.indices(&shape.triangles);
        let targets: Vec<_> = shape
            .targets
            .iter()
            .map(|t| json::mesh::MorphTarget {
                positions: Some(self.vectors(t, true)),
                normals: None,
                tangents: None,
            })
            .collect();
        let attributes = [
            (Valid(json::mesh::Semantic::Positions), positions),
            (Valid(json::mesh::Semantic::Normals), normals),
        ];
        Some(self.root.push(json::Mesh {
            name: Some(shape.name.clone()),
            primitives: vec![json::mesh::Primitive {
                attributes: attributes.into_iter().collect(),
                indices: Some(indices),
                material: Some(material),
                mode: Valid(json::mesh::Mode::Triangles),
                targets: (!targets.is_empty()).then_some(targets),
                extensions: None,
                extras: None,
            }],
            weights: None, // the node's weights (animated) are the ones used
            extensions: None,
            extras: None,
        }))
    }

    /// An animation channel on `node`'s `path`, sampled at `input`.
    pub(crate) fn channel(
        &mut self,
        animation: &mut json::Animation,
        input: json::Index<json::Accessor>,
        output: json::Index<json::Accessor>,
        node: json::Index<json::Node>,
        path: json::animation::Property,
    ) {
        let sampler = json::Index::push(
            &mut animation.samplers,
            json::animation::Sampler {
                input,
                output,
                interpolation: Valid(json::animation::Interpolation::Linear),
                extensions: None,
                extras: None,
            },
        );
        animation.channels.push(json::animation::Channel {
            sampler,
            target: json::animation::Target {
                node,
                path: Valid(path),
                extensions: None,
                extras: None,
            },
            extensions: None,
            extras: None,
        });
    }
}
