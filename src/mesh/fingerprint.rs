//! Pinned fingerprints of the meshes squeal generates itself (the built-in brake presets and
//! the test blocks), so that no refactoring of the meshers can change a mesh silently.
//!
//! A fingerprint is an FNV-1a hash per field of [`Mesh`]: node coordinates (their bits, so
//! a change in the last ulp counts), node labels, connectivity and element labels, parts and
//! materials, node sets, surfaces. Equal fingerprints mean the same nodes in the same order,
//! the same elements in the same order, and the same parts, sets and surfaces; the results
//! of every test and study built on these meshes are then unchanged too.
//!
//! Updating the pins is a deliberate act: when a mesher is changed ON PURPOSE (a new node
//! order, a different split), run
//! `cargo test --release --lib mesh::fingerprint -- --nocapture`, check that the change is
//! the one intended (the failure names the mesh and the field that moved), paste the printed
//! table over [`PINNED`] and say in the commit message why the meshes changed.

use std::collections::BTreeMap;

use super::block::block;
use super::brake;
use super::hash::{fingerprint, Fingerprint};
use super::{Material, Mesh};

/// The fields of a fingerprint, in order.
const FIELDS: [&str; 6] = [
    "nodes",
    "node_labels",
    "elements (with labels)",
    "parts and materials",
    "node_sets",
    "surfaces",
];

fn material(name: &str, young: f64) -> Material {
    Material {
        name: name.into(),
        young,
        poisson: 0.3,
        density: 7850.0,
    }
}

/// Every block the tests build (`tests/numerics/structure.rs`, `tests/numerics/contact_statics.rs`, the
/// contact unit tests, `block`'s own tests): origin, lengths, divisions.
const BLOCKS: [([f64; 3], [f64; 3], [usize; 3]); 15] = [
    ([1.0, 2.0, 3.0], [0.3, 0.2, 0.1], [3, 2, 2]),
    ([0.0; 3], [0.1, 0.04, 0.02], [6, 3, 2]),
    ([0.0; 3], [0.25, 0.02, 0.01], [10, 2, 1]),
    ([0.0; 3], [0.25, 0.02, 0.01], [20, 4, 2]),
    ([0.0; 3], [0.25, 0.02, 0.01], [40, 8, 4]),
    ([-0.02, -0.02, -0.02], [0.14, 0.10, 0.02], [7, 5, 1]),
    ([0.0; 3], [0.1, 0.06, 0.02], [6, 4, 1]),
    ([0.0, 0.0, -0.2], [1.0, 1.0, 0.2], [5, 5, 1]),
    ([0.2, 0.3, 0.0], [0.5, 0.3, 0.1], [3, 2, 1]),
    ([0.2, 0.3, 1e-3], [0.5, 0.3, 0.1], [3, 2, 1]),
    ([0.2, 0.3, 0.5], [0.5, 0.3, 0.1], [3, 2, 1]),
    ([0.8, 0.3, 0.0], [0.5, 0.3, 0.1], [5, 2, 1]),
    ([0.0, 0.0, -0.01], [1.0, 1.0, 0.01], [160, 160, 1]),
    ([0.2, 0.3, 0.0], [0.5, 0.4, 0.01], [35, 35, 1]),
    // Not used by a test: a block with every division different and an odd origin.
    ([-0.3, 0.7, 0.11], [0.9, 0.05, 0.3], [4, 1, 3]),
];

/// Every mesh that is pinned, by name.
fn meshes() -> Vec<(String, Box<dyn Fn() -> Mesh>)> {
    let mut out: Vec<(String, Box<dyn Fn() -> Mesh>)> = Vec::new();
    for &name in brake::PRESETS {
        out.push((
            format!("brake {name}"),
            Box::new(move || brake::build(&brake::preset(name).unwrap()).unwrap()),
        ));
    }
    // The options that change how the brake is meshed, on the tiny preset.
    let tiny = brake::preset("tiny").unwrap();
    let variants = [
        (
            "clockwise",
            brake::BrakeParams {
                rotation: brake::Rotation::Clockwise,
                ..tiny.clone()
            },
        ),
        (
            "gap, no ears, off-centre",
            brake::BrakeParams {
                pad_gap: 5e-4,
                backplate_overhang_deg: 0.0,
                pad_centre_deg: 37.0,
                ..tiny.clone()
            },
        ),
    ];
    for (what, p) in variants {
        out.push((
            format!("brake tiny {what}"),
            Box::new(move || brake::build(&p).unwrap()),
        ));
    }
    for (origin, lengths, divisions) in BLOCKS {
        out.push((
            format!("block {origin:?} {lengths:?} {divisions:?}"),
            Box::new(move || block(origin, lengths, divisions, material("steel", 210e9)).unwrap()),
        ));
    }
    out
}

/// Recorded from the meshers as they were before `mesh::structured` replaced them (commit
/// be80488), the floating-caliper presets when that layout was added; see the module doc
/// for how to update deliberately.
const PINNED: &[(&str, Fingerprint)] = &[
    (
        "brake tiny",
        [
            0x724e33ea30ad1f12,
            0x60a35658c1bfc828,
            0x618c474b9c89e2e9,
            0x8249ab984a17422b,
            0x7b4182ff242e2c0d,
            0x41c5fe27fddb4207,
        ],
    ),
    (
        "brake small",
        [
            0xadbcd9073582b6b6,
            0xa49ddcb71d7805c4,
            0xa0ad30b15181fc58,
            0xb51e4f6b38981724,
            0x866b25265761b73b,
            0x1303ab479bdd38ea,
        ],
    ),
    (
        "brake medium",
        [
            0x892df96c0b009fca,
            0x11470b29c3b4c108,
            0xdb4f0ace9b219900,
            0x30becf51f7a9d66c,
            0xc0ce8ce3929f5aaf,
            0x133ff9e35b0e4b1e,
        ],
    ),
    (
        "brake industrial",
        [
            0x6747d1ba970317e8,
            0x5bc2f02596d511a4,
            0x164dd2dba71fd09c,
            0xa8cab3035bc9f798,
            0x1ea83e1e1de94d5f,
            0xb9105ed32548b096,
        ],
    ),
    (
        "brake tiny-caliper",
        [
            0x0ab9bdb93098c81b,
            0x5976e3e093363074,
            0x75f7f4e3f43a4c65,
            0xee604e02f2d3e2e8,
            0xc3315e8c23c49ad5,
            0x1f57273556d94180,
        ],
    ),
    (
        "brake small-caliper",
        [
            0x3eb95495ff4333ff,
            0x475df206a5657409,
            0x46e1bc313821c03c,
            0xf52225fa9c34f81b,
            0xbb3dc74f905d05a8,
            0x74c7b3a6c47766c0,
        ],
    ),
    (
        "brake medium-caliper",
        [
            0x63a4ac2837b773da,
            0x1da349b9fba3a114,
            0x19a82e7205c21dd3,
            0xf89d900c21503666,
            0xbdddbab5448f6bc9,
            0x49fa0ce1fb174c43,
        ],
    ),
    (
        "brake industrial-caliper",
        [
            0xf3d7077ad8018f21,
            0x1dcbe918312e53fc,
            0xbee8989c05d7de68,
            0x45657448a63aa10c,
            0xb8e9b7b7385c8bf5,
            0xc43d7a8b08ad3dfd,
        ],
    ),
    (
        "brake tiny clockwise",
        [
            0x724e33ea30ad1f12,
            0x60a35658c1bfc828,
            0x618c474b9c89e2e9,
            0x8249ab984a17422b,
            0xd0e911a1d4bce431,
            0xffc406fd206eda0f,
        ],
    ),
    (
        "brake tiny gap, no ears, off-centre",
        [
            0x0f26ee0f202be4ce,
            0x03d25de4828d0d48,
            0x63d29791ce6aecf1,
            0x62988f90eabece5b,
            0x3422fc1fc3124873,
            0xe41235d826a28da7,
        ],
    ),
    (
        "block [1.0, 2.0, 3.0] [0.3, 0.2, 0.1] [3, 2, 2]",
        [
            0x11d9664e55e8f89f,
            0xef206a9bb682248a,
            0x5445dce3b363d06d,
            0x604a23e632645af1,
            0x6f94dc6b4b38453a,
            0x022d317a20ea348b,
        ],
    ),
    (
        "block [0.0, 0.0, 0.0] [0.1, 0.04, 0.02] [6, 3, 2]",
        [
            0xb37e16f19a5978e2,
            0x520d6c55305c9ea5,
            0x782a83ff3cf782df,
            0xdde9812708e57ac1,
            0x1c034e2089d76d2f,
            0x89e4ba35a60f616b,
        ],
    ),
    (
        "block [0.0, 0.0, 0.0] [0.25, 0.02, 0.01] [10, 2, 1]",
        [
            0x91b10f076a8b8dc1,
            0x79fa355352f2be95,
            0x5bc25656f03d3215,
            0x92f47dcdb3bb4b21,
            0x30fb03d1722a8c71,
            0xe2e5ff1550f484fb,
        ],
    ),
    (
        "block [0.0, 0.0, 0.0] [0.25, 0.02, 0.01] [20, 4, 2]",
        [
            0x37732e5b039f7441,
            0x72a3920d2c2a7d70,
            0xb44ccddd05d99c83,
            0x61ff769c783c4d6a,
            0x8911e1b9846df54e,
            0x65870ca537623886,
        ],
    ),
    (
        "block [0.0, 0.0, 0.0] [0.25, 0.02, 0.01] [40, 8, 4]",
        [
            0xb9bebbd91fd8a3be,
            0xcfd56d8f19f29bfd,
            0x343ea8a5e2b98be5,
            0x0f5c0a5728316713,
            0xdf355b7d0873dcf5,
            0x693546a62a8eaa5b,
        ],
    ),
    (
        "block [-0.02, -0.02, -0.02] [0.14, 0.1, 0.02] [7, 5, 1]",
        [
            0x3cde7cecd156fee7,
            0x181234331d30ff35,
            0x648c859c226a9308,
            0xd5714a4236fc0d30,
            0x03c289913aee6257,
            0x23f08f0ba28cf0e7,
        ],
    ),
    (
        "block [0.0, 0.0, 0.0] [0.1, 0.06, 0.02] [6, 4, 1]",
        [
            0x630225adca61767f,
            0x36c2703b24313055,
            0x04c035f2929dea92,
            0xfc8700556dcb6a39,
            0x7a6d878d36172ada,
            0x826b8578fbc2ff43,
        ],
    ),
    (
        "block [0.0, 0.0, -0.2] [1.0, 1.0, 0.2] [5, 5, 1]",
        [
            0x87212b7b6d0b3215,
            0x86cc4d1b783022f5,
            0x6f9095c6a2675e14,
            0x42c86ea22c241db4,
            0x21cc62506db05b74,
            0x7dc7a8a57142ddf3,
        ],
    ),
    (
        "block [0.2, 0.3, 0.0] [0.5, 0.3, 0.1] [3, 2, 1]",
        [
            0xebdf6e38fc94ad7a,
            0x7ffd7745e73954ed,
            0x09772fcec379b4e7,
            0x6a68e2b42fe93a2d,
            0x1a329f20868fddd6,
            0x5fa020261a4042b3,
        ],
    ),
    (
        "block [0.2, 0.3, 0.001] [0.5, 0.3, 0.1] [3, 2, 1]",
        [
            0xc09a4213c5f46bb6,
            0x7ffd7745e73954ed,
            0x09772fcec379b4e7,
            0x6a68e2b42fe93a2d,
            0x1a329f20868fddd6,
            0x5fa020261a4042b3,
        ],
    ),
    (
        "block [0.2, 0.3, 0.5] [0.5, 0.3, 0.1] [3, 2, 1]",
        [
            0x690acfa7d0f79ce6,
            0x7ffd7745e73954ed,
            0x09772fcec379b4e7,
            0x6a68e2b42fe93a2d,
            0x1a329f20868fddd6,
            0x5fa020261a4042b3,
        ],
    ),
    (
        "block [0.8, 0.3, 0.0] [0.5, 0.3, 0.1] [5, 2, 1]",
        [
            0x30c16e27f0ff75f0,
            0xb253bb1ab850b961,
            0x254777862a31c77f,
            0x80471bf407caba25,
            0x30f658d567901aea,
            0x9ee9c21ac5dc4bc3,
        ],
    ),
    (
        "block [0.0, 0.0, -0.01] [1.0, 1.0, 0.01] [160, 160, 1]",
        [
            0xd2305730d7ba8817,
            0x1ef03505c36c336f,
            0xd666c1483e6fde94,
            0x9838261890f37eab,
            0x8e7fbac95a6b822c,
            0x6498c2c4da0a083a,
        ],
    ),
    (
        "block [0.2, 0.3, 0.0] [0.5, 0.4, 0.01] [35, 35, 1]",
        [
            0x09106f4586489f51,
            0x6f0f36ce99807b4f,
            0xe6d80bb94beb6269,
            0x0cc8c596dd691870,
            0x7ddd46c417d26ef5,
            0x9dc311a256c84b16,
        ],
    ),
    (
        "block [-0.3, 0.7, 0.11] [0.9, 0.05, 0.3] [4, 1, 3]",
        [
            0xbd3d3e0dc5212b63,
            0xeed5b2676bd44bf9,
            0x61484f971fb1dd19,
            0x604a23e632645af1,
            0xba97ab31c884818b,
            0xc79bce8d7970c910,
        ],
    ),
];

#[test]
fn generated_meshes_are_unchanged() {
    let pinned: BTreeMap<&str, Fingerprint> = PINNED.iter().copied().collect();
    let mut table = String::new();
    let mut failures = Vec::new();
    for (name, make) in meshes() {
        let got = fingerprint(&make());
        table.push_str(&format!(
            "    (\n        \"{name}\",\n        [{}],\n    ),\n",
            got.map(|h| format!("{h:#018x}")).join(", ")
        ));
        match pinned.get(name.as_str()) {
            None => failures.push(format!("{name}: not pinned")),
            Some(want) => {
                for (field, (g, w)) in FIELDS.iter().zip(got.iter().zip(want)) {
                    if g != w {
                        failures.push(format!("{name}: {field} changed"));
                    }
                }
            }
        }
    }
    println!("const PINNED: &[(&str, Fingerprint)] = &[\n{table}];");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
