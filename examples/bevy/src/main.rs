//! The street at night in fog, in a window: a lamp post and a spot light glow
//! through `AirlightPlugin`.
//!
//! ```sh
//! cargo run --release -p airlight-bevy-example --features window
//! ```
//!
//! Drag with the left mouse button to orbit, scroll to zoom; keys 1, 2 and 3 pick
//! the quality (max error 3e-2, 1e-3, 3e-5: the cheapest kernel on the menu for
//! each); L toggles the spot light. The window's title shows the kernel and the
//! frame time.

use airlight_bevy::{AirlightFog, AirlightPlugin};
use airlight_bevy_example::{Spot, Street};
use bevy::camera::Exposure;
use bevy::core_pipeline::tonemapping::Tonemapping;
use bevy::diagnostic::{DiagnosticsStore, FrameTimeDiagnosticsPlugin};
use bevy::input::mouse::{AccumulatedMouseMotion, AccumulatedMouseScroll};
use bevy::prelude::*;

/// The orbit: yaw and pitch about the street's target, and the distance.
#[derive(Component)]
struct Orbit {
    yaw: f32,
    pitch: f32,
    distance: f32,
}

fn main() {
    App::new()
        .add_plugins((
            DefaultPlugins.set(WindowPlugin {
                primary_window: Some(Window { title: "airlight: street in fog".into(), ..default() }),
                ..default()
            }),
            FrameTimeDiagnosticsPlugin::default(),
            AirlightPlugin,
        ))
        .insert_resource(ClearColor(Color::BLACK))
        .add_systems(Startup, setup)
        .add_systems(Update, (orbit, quality, title))
        .run();
}

fn setup(mut commands: Commands, mut meshes: ResMut<Assets<Mesh>>, mut materials: ResMut<Assets<StandardMaterial>>) {
    let street = Street::default();
    street.spawn(&mut commands, &mut meshes, &mut materials);
    let offset = street.eye - street.target;
    commands.spawn((
        Camera3d::default(),
        Tonemapping::AcesFitted,
        Projection::Perspective(PerspectiveProjection { fov: street.fov, near: 0.05, ..default() }),
        Exposure { ev100: street.ev100 },
        street.camera_transform(),
        street.fog.clone(),
        Orbit { yaw: offset.x.atan2(offset.z), pitch: (offset.y / offset.length()).asin(), distance: offset.length() },
    ));
}

fn orbit(
    buttons: Res<ButtonInput<MouseButton>>,
    motion: Res<AccumulatedMouseMotion>,
    scroll: Res<AccumulatedMouseScroll>,
    mut cameras: Query<(&mut Orbit, &mut Transform)>,
) {
    let target = Street::default().target;
    for (mut o, mut t) in &mut cameras {
        if buttons.pressed(MouseButton::Left) {
            o.yaw -= motion.delta.x * 0.005;
            o.pitch = (o.pitch + motion.delta.y * 0.005).clamp(-0.2, 1.4);
        }
        o.distance = (o.distance * (1.0 - 0.1 * scroll.delta.y)).clamp(2.0, 30.0);
        let dir = Vec3::new(o.yaw.sin() * o.pitch.cos(), o.pitch.sin(), o.yaw.cos() * o.pitch.cos());
        *t = Transform::from_translation(target + dir * o.distance).looking_at(target, Vec3::Y);
    }
}

fn quality(
    keys: Res<ButtonInput<KeyCode>>,
    mut fogs: Query<&mut AirlightFog>,
    mut spots: Query<&mut Visibility, With<Spot>>,
) {
    let pick = [(KeyCode::Digit1, 3e-2), (KeyCode::Digit2, 1e-3), (KeyCode::Digit3, 3e-5)];
    for (key, max_error) in pick {
        if keys.just_pressed(key) {
            for mut f in &mut fogs {
                f.max_error = max_error;
            }
        }
    }
    if keys.just_pressed(KeyCode::KeyL) {
        for mut v in &mut spots {
            v.toggle_visible_hidden();
        }
    }
}

fn title(diagnostics: Res<DiagnosticsStore>, fogs: Query<&AirlightFog>, mut windows: Query<&mut Window>) {
    let ms = diagnostics
        .get(&FrameTimeDiagnosticsPlugin::FRAME_TIME)
        .and_then(|d| d.smoothed())
        .map_or(String::from("…"), |v| format!("{v:.2} ms"));
    let kernel = fogs.iter().next().and_then(|f| f.kernel().map(|k| k.name)).unwrap_or("none");
    for mut w in &mut windows {
        w.title = format!("airlight: street in fog, kernel {kernel}, frame {ms} (1 2 3: quality, L: spot)");
    }
}
