//! Each reason a GRAPHICS statement is no contact geometry, with its message and place.
