//! The small `Copy` handles the system's sets are addressed by: a part, a marker, a
//! constraint element. They are vocabulary, below the [`System`] that owns the sets, so
//! the data it holds (rows, measures) can name markers and parts without reading the
//! system.
//!
//! [`System`]: super::system::System

/// A part: index into [`System::parts`]; ground is [`System::GROUND`].
///
/// [`System::parts`]: super::system::System::parts
/// [`System::GROUND`]: super::system::System::GROUND
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PartHandle(pub u32);

/// A marker: index into [`System::markers`].
///
/// [`System::markers`]: super::system::System::markers
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct MarkerHandle(pub u32);

/// A constraint element: index into [`System::elements`].
///
/// [`System::elements`]: super::system::System::elements
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ElementHandle(pub u32);
