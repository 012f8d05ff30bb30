use super::SynthError;
use std::fmt;
use std::str::FromStr;

/// The synthetic scenes, each a moving implicit surface with a known ground truth.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Scene {
    /// Three blended metaballs rotating rigidly about a tilted axis, one full turn over the
    /// sequence: Stam & Schmidt's benchmark (paper §6).
    Blobs,
    /// Two spheres approaching until they merge: 2 → 1 components.
    Merge,
    /// A dumbbell whose bar thins and breaks, the stubs retracting: 1 → 2 components.
    Split,
    /// A ball with droplets appearing beside it, flying off and vanishing.
    Droplets,
    /// A sphere's signed distance blended linearly into a torus's: genus 0 → 1.
    Morph,
    /// A rounded box with a bump and a notch, translating and rotating rigidly.
    Rigid,
}

impl Scene {
    pub const ALL: [Scene; 6] = [
        Scene::Blobs,
        Scene::Merge,
        Scene::Split,
        Scene::Droplets,
        Scene::Morph,
        Scene::Rigid,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Scene::Blobs => "blobs",
            Scene::Merge => "merge",
            Scene::Split => "split",
            Scene::Droplets => "droplets",
            Scene::Morph => "morph",
            Scene::Rigid => "rigid",
        }
    }

    /// One line saying what happens in the scene.
    pub fn description(self) -> &'static str {
        match self {
            Scene::Blobs => "three blended metaballs rotating rigidly, one full turn",
            Scene::Merge => "two spheres approaching and merging (2 -> 1 components)",
            Scene::Split => "a dumbbell whose bar breaks (1 -> 2 components)",
            Scene::Droplets => "a ball with droplets appearing, flying off and vanishing",
            Scene::Morph => "a sphere blending into a torus (genus 0 -> 1)",
            Scene::Rigid => "a rounded box with a bump and a notch moving rigidly",
        }
    }
}

impl fmt::Display for Scene {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Scene {
    type Err = SynthError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Scene::ALL
            .into_iter()
            .find(|scene| scene.name().eq_ignore_ascii_case(s))
            .ok_or_else(|| SynthError::UnknownScene(s.to_string()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for scene in Scene::ALL {
            assert_eq!(scene.to_string().parse::<Scene>().unwrap(), scene);
        }
        assert_eq!("MERGE".parse::<Scene>().unwrap(), Scene::Merge);
        assert!(matches!(
            "bubbles".parse::<Scene>(),
            Err(SynthError::UnknownScene(name)) if name == "bubbles"
        ));
    }
}
