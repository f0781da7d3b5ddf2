//! Speed against accuracy: the scenes with truth ([`scene`]), one measured run
//! ([`point`]), the work-precision grid ([`wp`]), the stability suite ([`stability`]) with the peers' cells ([`peer_cells`]),
//! scaling with model size ([`scaling`]), the charts ([`chart`]) and the datasets
//! written for any size ([`generate`]), and whether the runs' accuracy warnings mean
//! something ([`alarms`]). `mbfx bench` is the command-line face.

pub mod alarms;
pub mod chart;
pub mod generate;
pub mod orders;
pub mod output;
pub mod peer_cells;
pub mod point;
pub mod scaling;
pub mod scene;
pub mod stability;
pub mod wp;
