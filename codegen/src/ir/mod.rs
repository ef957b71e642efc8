//! Stage 3 (IR): the hash-consed expression [`dag::Dag`], the lowering of a model's loops and
//! points into scalar residuals and coordinates on it ([`lower`]), and symbolic derivatives in the
//! same DAG ([`differentiate`]): J, Φx, J̇, the velocity and acceleration right-hand sides.

pub mod dag;
pub mod differentiate;
pub mod lower;
