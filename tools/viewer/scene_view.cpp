#include "scene_view.hpp"

#include <khz/reduced/subspace/vertex_normals.hpp>
#include <khz/viewer/force_arrow.hpp>

#include <GL/gl.h>

#include <algorithm>
#include <cmath>

namespace khz::viewer {
namespace {

void set_color(const render::Color& color) { glColor3ub(color.r, color.g, color.b); }

/// OpenGL's projection of `camera` (column-major, eye coordinates → clip coordinates): the same
/// vertical angle and aspect ratio, so a world point lands on the pixel camera.project() gives.
Eigen::Matrix4d projection(const render::Camera& camera, double near, double far) {
  const double f = 1.0 / std::tan(0.5 * camera.vertical_fov());
  const double aspect = static_cast<double>(camera.width()) / camera.height();
  Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
  m(0, 0) = f / aspect;
  m(1, 1) = f;
  m(2, 2) = (far + near) / (near - far);
  m(2, 3) = 2.0 * far * near / (near - far);
  m(3, 2) = -1.0;
  return m;
}

/// World → OpenGL eye coordinates (x right, y up, looking down −z) of `camera`.
Eigen::Matrix4d view(const render::Camera& camera) {
  Eigen::Matrix3d rotation;
  rotation.row(0) = camera.right();
  rotation.row(1) = camera.up();
  rotation.row(2) = -camera.forward();
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = rotation;
  m.topRightCorner<3, 1>() = -rotation * camera.eye();
  return m;
}

void line(const Eigen::Vector3d& from, const Eigen::Vector3d& to) {
  glVertex3dv(from.data());
  glVertex3dv(to.data());
}

/// An arrow from `from` to `to`: a line and a flat head facing the camera, a quarter of the
/// arrow long (at most `head` m). Nothing for an arrow too short to see.
void arrow(const Eigen::Vector3d& from, const Eigen::Vector3d& to, const render::Camera& camera,
           double head, double shortest) {
  const Eigen::Vector3d shaft = to - from;
  const double length = shaft.norm();
  if (!(length > shortest)) return;
  const Eigen::Vector3d along = shaft / length;
  Eigen::Vector3d across = along.cross(camera.forward());
  across = across.norm() > 1e-6 ? across.normalized() : camera.right();  // along the view: any
  const double h = std::min(0.25 * length, head);
  const Eigen::Vector3d base = to - h * along;
  glBegin(GL_LINES);
  line(from, base);
  glEnd();
  glBegin(GL_TRIANGLES);
  for (const Eigen::Vector3d& corner :
       {to, Eigen::Vector3d(base + 0.4 * h * across), Eigen::Vector3d(base - 0.4 * h * across)}) {
    glVertex3dv(corner.data());
  }
  glEnd();
}

}  // namespace

/// One object as drawn: its surface (body frame) and how it deforms.
struct SceneView::Body {
  reduced::TriangleMatrix triangles;
  std::unique_ptr<reduced::EmbeddedSurface> embedded;  // reduced objects only
  render::Color color;
  bool smooth = false;
  reduced::VertexMatrix positions;  // this frame's, body frame
  reduced::VertexMatrix normals;    // smooth bodies: this frame's vertex normals
};

SceneView::SceneView(const scene::SceneRuntime& runtime, const SnapshotLayout& layout,
                     const run::SceneFraming& framing)
    : m_layout(layout),
      m_points(runtime, layout),
      m_radius(framing.radius),
      m_reference_force(run::arrow_reference_force(runtime.description())) {
  for (int h = 0; h < runtime.hand_count(); ++h) {
    m_held_objects.push_back(runtime.held_object(h));
    m_grasps_in_body.push_back(runtime.grasp_in_body(h));
  }
  for (int i = 0; i < static_cast<int>(runtime.description().objects.size()); ++i) {
    const reduced::TriangleMesh& surface = runtime.surface(i);
    auto body = std::make_unique<Body>();
    body->triangles = surface.triangles;
    const scene::PreparedObject& products = runtime.prepared().objects[static_cast<std::size_t>(i)];
    if (runtime.integrator(i) != nullptr) {
      body->embedded = std::make_unique<reduced::EmbeddedSurface>(*products.embedding, surface,
                                                                  products.model->basis().vectors);
    }
    body->color = run::surface_color(m_colors, runtime, i);
    body->smooth = run::shade_smoothly(surface.triangles);
    body->positions = surface.vertices;
    body->normals.resize(surface.vertices.rows(), 3);
    if (body->smooth) reduced::vertex_normals(body->positions, body->triangles, body->normals);
    m_bodies.push_back(std::move(body));
  }
}

SceneView::~SceneView() = default;

void SceneView::draw(const SceneSnapshot& snapshot, const render::Camera& camera, int width,
                     int height) {
  glViewport(0, 0, width, height);
  glClearColor(1.0f, 1.0f, 1.0f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);

  const double distance = (camera.target() - camera.eye()).norm();
  glMatrixMode(GL_PROJECTION);
  glLoadMatrixd(projection(camera, 0.1 * distance, distance + 4.0 * m_radius).data());
  glMatrixMode(GL_MODELVIEW);
  glLoadIdentity();
  // A headlight: a directional light from the eye, set in eye coordinates.
  const GLfloat towards_eye[] = {0.0f, 0.0f, 1.0f, 0.0f};
  const GLfloat ambient[] = {0.25f, 0.25f, 0.25f, 1.0f};
  glLightfv(GL_LIGHT0, GL_POSITION, towards_eye);
  glLightModelfv(GL_LIGHT_MODEL_AMBIENT, ambient);
  glLightModeli(GL_LIGHT_MODEL_TWO_SIDE, GL_TRUE);
  glEnable(GL_LIGHT0);
  glEnable(GL_COLOR_MATERIAL);
  glColorMaterial(GL_FRONT_AND_BACK, GL_AMBIENT_AND_DIFFUSE);
  glLoadMatrixd(view(camera).data());

  glEnable(GL_LIGHTING);
  // Surfaces a little behind their depth, so that points on them are not hidden by them.
  glEnable(GL_POLYGON_OFFSET_FILL);
  glPolygonOffset(1.0f, 1.0f);
  for (std::size_t i = 0; i < m_bodies.size(); ++i) {
    draw_body(*m_bodies[i], snapshot.poses[i], m_layout.coordinates(snapshot, static_cast<int>(i)));
  }
  glDisable(GL_POLYGON_OFFSET_FILL);
  glDisable(GL_LIGHTING);

  draw_points(snapshot);
  draw_hands(snapshot, camera);
}

void SceneView::draw_points(const SceneSnapshot& snapshot) {
  // As the frame pictures: points looked at are depth-tested; points in contact lie inside the
  // other object, so they are drawn over it.
  const std::vector<run::PointPicture>& pictures = m_points.classify(snapshot);
  for (const run::PointState state :
       {run::PointState::traversed, run::PointState::in_contact, run::PointState::sliding}) {
    const bool touching = state != run::PointState::traversed;
    if (touching) glDisable(GL_DEPTH_TEST);
    glPointSize(touching ? 5.0f : 3.0f);
    set_color(!touching                              ? m_colors.traversed_color
              : state == run::PointState::in_contact ? m_colors.contact_color
                                                     : m_colors.sliding_color);
    glBegin(GL_POINTS);
    for (const run::PointPicture& picture : pictures) {
      for (std::size_t s = 0; s < picture.states.size(); ++s) {
        if (picture.states[s] == state) {
          glVertex3dv(picture.positions.row(static_cast<Eigen::Index>(s)).data());
        }
      }
    }
    glEnd();
  }
}

void SceneView::draw_hands(const SceneSnapshot& snapshot, const render::Camera& camera) const {
  // Drawn over everything: each hand's coupling spring and contact force.
  glDisable(GL_DEPTH_TEST);
  const double extent = view_half_extent(camera, camera.target());
  for (std::size_t h = 0; h < m_grasps_in_body.size(); ++h) {
    const haptic::CycleRecord& record = snapshot.records[h];
    const Eigen::Vector3d grasp =
        snapshot.poses[static_cast<std::size_t>(m_held_objects[h])] * m_grasps_in_body[h];
    const Eigen::Vector3d& device = record.manipulandum.position;
    glLineWidth(1.5f);
    set_color(m_colors.traversed_color);
    glBegin(GL_LINES);
    line(grasp, device);
    glEnd();
    glPointSize(8.0f);
    glBegin(GL_POINTS);
    glVertex3dv(device.data());
    glEnd();
    glLineWidth(3.0f);
    set_color(m_colors.force_color);
    const Eigen::Vector3d& force = record.contact.force;
    const double magnitude = force.norm();
    if (!std::isfinite(magnitude) || !(magnitude > 0.0)) continue;
    const double room = room_in_view(camera, grasp, force / magnitude, arrow_margin);
    const ArrowScale scale{m_reference_force, m_radius,
                           std::min(arrow_view_fraction * extent, room)};
    arrow(grasp, grasp + scale.arrow(force), camera, 0.08 * extent, 1e-3 * extent);
  }
}

void SceneView::draw_body(Body& body, const Eigen::Isometry3d& pose,
                          const Eigen::Map<const Eigen::VectorXd>& q) const {
  if (body.embedded != nullptr) {
    body.embedded->deformed_positions(q, body.positions);
    if (body.smooth) reduced::vertex_normals(body.positions, body.triangles, body.normals);
  }
  glPushMatrix();
  glMultMatrixd(pose.matrix().data());
  set_color(body.color);
  glBegin(GL_TRIANGLES);
  for (Eigen::Index t = 0; t < body.triangles.rows(); ++t) {
    const auto corners = body.triangles.row(t);
    if (!body.smooth) {
      const Eigen::Vector3d a = body.positions.row(corners[0]);
      const Eigen::Vector3d normal = (Eigen::Vector3d(body.positions.row(corners[1])) - a)
                                         .cross(Eigen::Vector3d(body.positions.row(corners[2])) - a)
                                         .normalized();
      glNormal3dv(normal.data());
    }
    for (const int v : {corners[0], corners[1], corners[2]}) {
      if (body.smooth) glNormal3dv(body.normals.row(v).data());
      glVertex3dv(body.positions.row(v).data());
    }
  }
  glEnd();
  glPopMatrix();
}

}  // namespace khz::viewer
