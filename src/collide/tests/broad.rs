//! The broad phase: only pairs whose bounding boxes overlap are candidates.
