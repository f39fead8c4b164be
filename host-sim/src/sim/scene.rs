//! Scenes are data: the scene files and their loader live in `softfinger-scene`, which the host
//! command line shares without the simulator; re-exported here under their old path.

pub use softfinger_scene::file::*;
