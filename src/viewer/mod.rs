//! The self-contained HTML page of an animation: the project's WebGL2 viewer, with the
//! `.glb` and the run's columns inlined; nothing is fetched at view time.
