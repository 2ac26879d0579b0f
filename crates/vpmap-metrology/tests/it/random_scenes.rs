//! random_scenes
