//! The technique registry: one row per wireframe technique, read by everything that
//! names, lists, builds or sizes techniques (the renderer, the command line, the tests
//! and the benchmarks). Adding a technique means its own module, a [`WireMode`]
//! variant and its row in [`TECHNIQUES`].

use super::{PipelineContext, Technique, bias, distance, idbuffer, texture};

/// The wireframe techniques. Each variant has its row in [`TECHNIQUES`], in
/// declaration order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum WireMode {
    /// Shaded surface only: the reference every technique is measured against.
    None,
    /// Global odd texture coordinates of structured meshes (2i + 1, 2j + 1): draws the
    /// original grid on any surface that carries them, decimated ones included.
    Global,
    /// Per-quad -1 / +1 coordinates (cell faces).
    Quad,
    /// Per-vertex α/β/γ labels found by a breadth-first search, duplicating on conflict.
    Tex,
    /// Per-triangle coordinates made while pulling vertices (no duplication).
    TexGs,
    /// Classic two passes: the fill pushed back by a depth bias, then line primitives
    /// (screen-space quads for lines wider than a pixel).
    Bias,
    /// Bærentzen's single pass: each fragment's window-space distance to its
    /// triangle's real edges, with Gateau's case for vertices behind the eye.
    Dist,
    /// Bærentzen's ID-buffer method: polygon IDs, then line quads kept where the ID
    /// matches or the depth test passes, then shading.
    IdBuffer,
}

/// How a technique finds its lines, which decides what can be varied and compared.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Family {
    /// Lines from texture coordinates (Celes & Abraham): each comes in both
    /// [`Coverage`](crate::Coverage) forms and carries isolines and grid lines.
    Texture,
    /// Lines from the triangles' own edges (depth bias, distance, ID buffer).
    Edges,
}

/// What a technique needs of a mesh beyond triangles, so that lists of techniques
/// offer only those a mesh can draw; ordered from the least demanding.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Needs {
    /// Any triangle mesh.
    Triangles,
    /// Global coordinates of a structured mesh.
    GlobalCoordinates,
    /// A mesh made of cell faces (quads).
    CellFaces,
}

/// Bytes a technique holds per active cell at its peak, for refusing a drawing that
/// would not fit in memory before starting it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CellBytes {
    /// Drawing lines only.
    pub plain: f64,
    /// Drawing isolines too.
    pub with_isolines: f64,
}

/// One technique's registration: everything about it that is not its module.
pub struct Registration {
    /// The technique this row describes.
    pub mode: WireMode,
    /// Its name on command lines and in benchmark JSON.
    pub name: &'static str,
    /// How it finds its lines.
    pub family: Family,
    /// What a mesh must carry for it.
    pub needs: Needs,
    /// See [`WireMode::draws_alone`].
    pub draws_alone: bool,
    /// Peak memory per active cell: `strata render` measured on a 1300 x 1300 layer
    /// on lavapipe, rounded up (`docs/performance.md`, "Drawing in parts, and memory").
    pub bytes_per_cell: CellBytes,
    /// Builds the technique's pipelines.
    pub create: fn(&PipelineContext) -> Box<dyn Technique>,
}

/// The edge techniques' peak, the same with isolines, which they do not draw.
const EDGE_BYTES: CellBytes = CellBytes {
    plain: 1400.0,
    with_isolines: 1400.0,
};

/// The registry, one row per [`WireMode`] in declaration order.
pub const TECHNIQUES: [Registration; 8] = [
    Registration {
        mode: WireMode::None,
        name: "none",
        family: Family::Texture,
        needs: Needs::Triangles,
        draws_alone: true,
        bytes_per_cell: CellBytes {
            plain: 850.0,
            with_isolines: 1200.0,
        },
        create: |ctx| Box::new(texture::VertexTechnique::new(WireMode::None, ctx)),
    },
    Registration {
        mode: WireMode::Global,
        name: "global",
        family: Family::Texture,
        needs: Needs::GlobalCoordinates,
        draws_alone: true,
        bytes_per_cell: CellBytes {
            plain: 850.0,
            with_isolines: 1200.0,
        },
        create: |ctx| Box::new(texture::VertexTechnique::new(WireMode::Global, ctx)),
    },
    Registration {
        mode: WireMode::Quad,
        name: "quad",
        family: Family::Texture,
        needs: Needs::CellFaces,
        draws_alone: true,
        bytes_per_cell: CellBytes {
            plain: 850.0,
            with_isolines: 1200.0,
        },
        create: |ctx| Box::new(texture::VertexTechnique::new(WireMode::Quad, ctx)),
    },
    Registration {
        mode: WireMode::Tex,
        name: "tex",
        family: Family::Texture,
        needs: Needs::Triangles,
        draws_alone: true,
        bytes_per_cell: CellBytes {
            plain: 1600.0,
            with_isolines: 1600.0,
        },
        create: |ctx| Box::new(texture::VertexTechnique::new(WireMode::Tex, ctx)),
    },
    Registration {
        mode: WireMode::TexGs,
        name: "texgs",
        family: Family::Texture,
        needs: Needs::Triangles,
        draws_alone: true,
        bytes_per_cell: CellBytes {
            plain: 850.0,
            with_isolines: 1200.0,
        },
        create: |ctx| Box::new(texture::PulledTechnique::new(ctx)),
    },
    Registration {
        mode: WireMode::Bias,
        name: "bias",
        family: Family::Edges,
        needs: Needs::Triangles,
        draws_alone: false,
        bytes_per_cell: EDGE_BYTES,
        create: |ctx| Box::new(bias::BiasTechnique::new(ctx)),
    },
    Registration {
        mode: WireMode::Dist,
        name: "dist",
        family: Family::Edges,
        needs: Needs::Triangles,
        draws_alone: true,
        bytes_per_cell: EDGE_BYTES,
        create: |ctx| Box::new(distance::DistTechnique::new(ctx)),
    },
    Registration {
        mode: WireMode::IdBuffer,
        name: "idbuffer",
        family: Family::Edges,
        needs: Needs::Triangles,
        draws_alone: false,
        bytes_per_cell: EDGE_BYTES,
        create: |ctx| Box::new(idbuffer::IdBufferTechnique::new(ctx)),
    },
];

// Rows in declaration order, so that a mode finds its row by its discriminant.
const _: () = {
    let mut i = 0;
    while i < TECHNIQUES.len() {
        assert!(TECHNIQUES[i].mode as usize == i);
        i += 1;
    }
};

impl WireMode {
    /// Every technique, in registry order.
    pub const ALL: [WireMode; TECHNIQUES.len()] = {
        let mut all = [WireMode::None; TECHNIQUES.len()];
        let mut i = 0;
        while i < all.len() {
            all[i] = TECHNIQUES[i].mode;
            i += 1;
        }
        all
    };

    /// This technique's row of the registry.
    pub fn registration(self) -> &'static Registration {
        &TECHNIQUES[self as usize]
    }

    /// Its name on command lines and in benchmark JSON.
    pub fn name(self) -> &'static str {
        self.registration().name
    }

    /// How it finds its lines.
    pub fn family(self) -> Family {
        self.registration().family
    }

    /// Whether it draws the outline's outer half and fault traces as geometry after
    /// the surface (`Renderer::prepare`): the texture techniques, whose lines come
    /// from coordinates, but `none`, which draws no lines.
    pub fn draws_edges(self) -> bool {
        self.family() == Family::Texture && self != WireMode::None
    }

    /// What a mesh must carry for it.
    pub fn needs(self) -> Needs {
        self.registration().needs
    }

    /// The techniques of `family`, in registry order.
    pub fn of_family(family: Family) -> impl Iterator<Item = WireMode> {
        Self::ALL.into_iter().filter(move |m| m.family() == family)
    }

    /// Whether the technique's lines are drawn with its polygons, each fragment seeing
    /// only the depth left before it, so that a scene drawn a part at a time
    /// ([`crate::Renderer::render_parts`]) looks as drawn at once. Not `bias`, which
    /// draws every line after every fill (a later part's fill covers the half of a
    /// line that lay over it), nor `idbuffer`, whose ID buffer holds one drawable's
    /// polygons.
    pub fn draws_alone(self) -> bool {
        self.registration().draws_alone
    }

    /// Bytes held per active cell at the peak of a drawing, with or without
    /// isolines, to refuse a drawing that would not fit before starting it.
    pub fn bytes_per_cell(self, isolines: bool) -> f64 {
        let bytes = self.registration().bytes_per_cell;
        if isolines {
            bytes.with_isolines
        } else {
            bytes.plain
        }
    }

    /// The technique named `name`, ignoring case.
    pub fn from_name(name: &str) -> Option<Self> {
        TECHNIQUES
            .iter()
            .find(|t| t.name.eq_ignore_ascii_case(name))
            .map(|t| t.mode)
    }
}

/// Names of the wire modes, for command lines and benchmark JSON.
pub fn wire_mode_names() -> Vec<&'static str> {
    TECHNIQUES.iter().map(|t| t.name).collect()
}

/// The technique of `mode`, its pipelines built.
pub fn create(mode: WireMode, ctx: &PipelineContext) -> Box<dyn Technique> {
    (mode.registration().create)(ctx)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_mode_is_found_by_its_name_in_any_case() {
        for mode in WireMode::ALL {
            assert_eq!(WireMode::from_name(mode.name()), Some(mode));
            assert_eq!(WireMode::from_name(&mode.name().to_uppercase()), Some(mode));
        }
        assert_eq!(WireMode::from_name("wire"), None);
        assert_eq!(wire_mode_names().len(), WireMode::ALL.len());
    }
}
