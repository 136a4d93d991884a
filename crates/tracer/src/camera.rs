//! (in progress)
pub struct Camera;
