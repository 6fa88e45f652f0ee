//! The street of the Bevy example: a lamp post and a wall-mounted spot light in
//! fog, a bench and a kerb, all boxes (so that the headless test knows every
//! surface exactly). `spawn` builds it in a Bevy world.

use airlight_bevy::{AirlightFog, AirlightPlugin};
use bevy::prelude::*;

/// The README's Bevy quick start (compiled with this crate by `cargo test`; the
/// street below is what the headless test draws): the plugin, a camera whose
/// frame gets the fog, and a lamp that glows in it — every visible `PointLight`
/// and `SpotLight` does.
pub fn quick_start(app: &mut App) {
    app.add_plugins(AirlightPlugin);
    app.add_systems(Startup, |mut commands: Commands| {
        commands.spawn((
            Camera3d::default(),
            Transform::from_xyz(0.0, 1.7, 8.0).looking_at(Vec3::new(0.0, 2.0, 0.0), Vec3::Y),
            AirlightFog { sigma_t: Vec3::splat(0.06), sigma_s: Vec3::splat(0.05), g: 0.6, max_error: 1e-3 },
        ));
        commands.spawn((PointLight { intensity: 100_000.0, ..default() }, Transform::from_xyz(0.0, 4.0, 0.0)));
    });
}

/// An axis-aligned box: its corners and its (unlit) colour.
#[derive(Clone, Copy, Debug)]
pub struct Block {
    pub min: Vec3,
    pub max: Vec3,
    pub colour: Color,
}

/// The street: its blocks, its lights, the medium and the camera.
#[derive(Clone, Debug)]
pub struct Street {
    pub blocks: Vec<Block>,
    pub lamp: (PointLight, Vec3),
    /// The spot light, its position and the point it aims at.
    pub spot: (SpotLight, Vec3, Vec3),
    pub fog: AirlightFog,
    /// The camera's eye, the point it looks at, its vertical field of view (radians).
    pub eye: Vec3,
    pub target: Vec3,
    pub fov: f32,
    /// The camera's exposure (EV100).
    pub ev100: f32,
}

/// A dark colour of linear `v`.
fn grey(v: f32) -> Color {
    Color::linear_rgb(v, v, v)
}

impl Default for Street {
    fn default() -> Self {
        let block = |min: [f32; 3], max: [f32; 3], colour: Color| Block { min: min.into(), max: max.into(), colour };
        Self {
            blocks: vec![
                // The road and the pavement, the facade behind them.
                block([-14.0, -0.2, -8.0], [14.0, 0.0, 10.0], grey(0.02)),
                block([-14.0, 0.0, -6.0], [14.0, 0.15, -2.5], grey(0.05)),
                block([-14.0, 0.0, -6.4], [14.0, 9.0, -6.0], Color::linear_rgb(0.06, 0.04, 0.03)),
                // The lamp post and its arm.
                block([-3.08, 0.15, -3.58], [-2.92, 4.4, -3.42], grey(0.01)),
                block([-3.08, 4.4, -3.58], [-2.92, 4.52, -2.6], grey(0.01)),
                // A bench: seat and back.
                block([0.5, 0.45, -4.2], [2.3, 0.55, -3.7], Color::linear_rgb(0.08, 0.05, 0.02)),
                block([0.5, 0.55, -4.25], [2.3, 1.0, -4.15], Color::linear_rgb(0.08, 0.05, 0.02)),
                // A doorway's step under the spot.
                block([3.0, 0.15, -6.0], [5.0, 0.3, -5.4], grey(0.04)),
            ],
            lamp: (
                PointLight {
                    color: Color::linear_rgb(1.0, 0.78, 0.5),
                    intensity: 60_000.0,
                    range: 9.0,
                    shadow_maps_enabled: false,
                    ..default()
                },
                Vec3::new(-3.0, 4.25, -2.75),
            ),
            spot: (
                SpotLight {
                    color: Color::linear_rgb(0.6, 0.75, 1.0),
                    intensity: 120_000.0,
                    range: 25.0,
                    outer_angle: 0.55,
                    inner_angle: 0.35,
                    shadow_maps_enabled: false,
                    ..default()
                },
                Vec3::new(4.0, 5.5, -5.7),
                Vec3::new(4.5, 0.0, -2.0),
            ),
            fog: AirlightFog {
                sigma_t: Vec3::new(0.055, 0.06, 0.07),
                sigma_s: Vec3::new(0.05, 0.055, 0.064),
                g: 0.6,
                max_error: 1e-3,
            },
            eye: Vec3::new(-0.5, 1.7, 7.0),
            target: Vec3::new(0.5, 2.2, -3.0),
            fov: 1.0,
            ev100: 4.0,
        }
    }
}

/// Marks the street's lamp (a point light) and spot light.
#[derive(Component)]
pub struct Lamp;
#[derive(Component)]
pub struct Spot;

impl Street {
    /// Spawns the blocks (unlit: their colour is what the camera sees, whatever
    /// the lights) and the two lights; the camera is the caller's.
    pub fn spawn(&self, commands: &mut Commands, meshes: &mut Assets<Mesh>, materials: &mut Assets<StandardMaterial>) {
        for b in &self.blocks {
            let size = b.max - b.min;
            commands.spawn((
                Mesh3d(meshes.add(Cuboid::new(size.x, size.y, size.z))),
                MeshMaterial3d(materials.add(StandardMaterial { base_color: b.colour, unlit: true, ..default() })),
                Transform::from_translation((b.min + b.max) * 0.5),
            ));
        }
        commands.spawn((self.lamp.0, Transform::from_translation(self.lamp.1), Lamp));
        let (spot, at, aim) = &self.spot;
        commands.spawn((*spot, Transform::from_translation(*at).looking_at(*aim, Vec3::Y), Spot));
    }

    /// The camera's transform.
    pub fn camera_transform(&self) -> Transform {
        Transform::from_translation(self.eye).looking_at(self.target, Vec3::Y)
    }
}
