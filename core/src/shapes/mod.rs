//! The shape files a scene names, as data: where they are found ([`assets`]), OBJ and
//! STL meshes ([`mesh`]), terrain height maps ([`heightmap`]) and how a file's kind is
//! told ([`shape_file`]). Part of the scene layer: it imports no geometry.

pub mod assets;
pub mod heightmap;
pub mod mesh;
pub mod shape_file;
