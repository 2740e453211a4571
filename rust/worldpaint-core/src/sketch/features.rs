//! Terrain features: silhouettes and ridges (thesis §5.3.1).
