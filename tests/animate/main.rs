//! `mbfx run --animate`: the .glb writer on hand-made scenes (`writer`), a run's glTF
//! read back against its own probes, the CSV left alone, failures (`run`), and the
//! corpus census (`census`). The Khronos validator runs through node (`validator`).

mod census;
mod figures;
mod run;
mod validator;
mod writer;
