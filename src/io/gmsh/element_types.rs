//! The Gmsh element types squeal reads (10-node tetrahedra, the triangles, lines and points
//! that carry physical groups), and the sentence that refuses every other type by name.

/// The element types squeal reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Kind {
    Point,
    Line2,
    Line3,
    Tri3,
    Tri6,
    Tet10,
}

impl Kind {
    pub(super) fn from_gmsh(element_type: i32) -> Option<Kind> {
        Some(match element_type {
            15 => Kind::Point,
            1 => Kind::Line2,
            8 => Kind::Line3,
            2 => Kind::Tri3,
            9 => Kind::Tri6,
            11 => Kind::Tet10,
            _ => return None,
        })
    }

    pub(super) fn nodes(self) -> usize {
        match self {
            Kind::Point => 1,
            Kind::Line2 => 2,
            Kind::Line3 | Kind::Tri3 => 3,
            Kind::Tri6 => 6,
            Kind::Tet10 => 10,
        }
    }

    pub(super) fn dim(self) -> i32 {
        match self {
            Kind::Point => 0,
            Kind::Line2 | Kind::Line3 => 1,
            Kind::Tri3 | Kind::Tri6 => 2,
            Kind::Tet10 => 3,
        }
    }
}

/// Gmsh's name for an element type (manual, "MSH file format", elm-type list).
pub(super) fn type_name(element_type: i32) -> Option<&'static str> {
    Some(match element_type {
        1 => "2-node line",
        2 => "3-node triangle",
        3 => "4-node quadrangle",
        4 => "4-node tetrahedron",
        5 => "8-node hexahedron",
        6 => "6-node prism",
        7 => "5-node pyramid",
        8 => "3-node line",
        9 => "6-node triangle",
        10 => "9-node quadrangle",
        11 => "10-node tetrahedron",
        12 => "27-node hexahedron",
        13 => "18-node prism",
        14 => "14-node pyramid",
        15 => "1-node point",
        16 => "8-node quadrangle",
        17 => "20-node hexahedron",
        18 => "15-node prism",
        19 => "13-node pyramid",
        20 => "9-node incomplete triangle",
        21 => "10-node triangle",
        22 => "12-node incomplete triangle",
        23 => "15-node triangle",
        24 => "15-node incomplete triangle",
        25 => "21-node triangle",
        26 => "4-node line",
        27 => "5-node line",
        28 => "6-node line",
        29 => "20-node tetrahedron",
        30 => "35-node tetrahedron",
        31 => "56-node tetrahedron",
        92 => "64-node hexahedron",
        93 => "125-node hexahedron",
        _ => return None,
    })
}

/// The message refusing an element type squeal does not read.
pub(super) fn refusal(element_type: i32) -> String {
    let Some(name) = type_name(element_type) else {
        return format!(
            "element type {element_type} is not a Gmsh element type squeal knows: squeal needs \
             10-node tetrahedra (type 11)"
        );
    };
    let why = match element_type {
        4 | 29 | 30 | 31 => "squeal needs 10-node tetrahedra (type 11); mesh with -order 2",
        5 | 6 | 7 | 12 | 13 | 14 | 17 | 18 | 19 | 92 | 93 => {
            "squeal needs 10-node tetrahedra (type 11); mesh every volume with tetrahedra, \
             with -order 2"
        }
        3 | 10 | 16 | 20..=25 => {
            "physical surfaces must be made of 6-node (type 9) or 3-node (type 2) triangles"
        }
        _ => "physical curves must be made of 3-node (type 8) or 2-node (type 1) lines",
    };
    format!("element type {element_type} ({name}) is not supported: {why}")
}

#[cfg(test)]
mod tests {
    use super::super::test_support::*;

    #[test]
    fn other_element_types_are_refused_by_name() {
        let text = TWO_TETS_41.replace(
            "3 2 11 1\n8 2 3 4 5 12 16 15 17 19 18",
            "3 2 4 1\n8 2 3 4 5",
        );
        let (line, message) = parse_error(&text);
        assert_eq!(line, line_of(&text, "3 2 4 1"));
        assert_eq!(
            message,
            "element type 4 (4-node tetrahedron) is not supported: squeal needs 10-node \
             tetrahedra (type 11); mesh with -order 2"
        );
        let text = TWO_TETS_22.replace("20 9 2 3 1 3 5 4 18 19 16", "20 3 2 3 1 3 5 4 18");
        let (line, message) = parse_error(&text);
        assert_eq!(line, line_of(&text, "20 3 2"));
        assert!(message.starts_with("element type 3 (4-node quadrangle) is not supported"));
    }
}
