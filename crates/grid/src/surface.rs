//! Layer and side surfaces of a grid as attributed triangle meshes.
