//! Parametric generators: the paper's three test parts (§VII: chair, shelf, stool) and two
//! that only plan with the 2F-85 as it really closes (bench end, ladder), and generated parts
//! of six families for sweeps ([`families`]) and of six hard-case families that put material
//! next to the grasps ([`hard`]).

pub mod bench_end;
pub mod chair;
pub mod families;
pub mod hard;
mod kit;
pub mod ladder;
pub mod shelf;
pub mod stool;
