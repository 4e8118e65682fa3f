#include "nodes/synth/or_scene.hpp"

#include <cmath>
#include <stdexcept>

#include "nodes/synth/stream_purpose.hpp"

namespace gslift::synth {

namespace {

using Vec3 = Eigen::Vector3f;
constexpr float kPi = 3.14159265358979f;

// Room extent (metres): x along the operating table, z up, floor at z = 0.
constexpr float kRoomX = 4.0f, kRoomY = 3.0f, kRoomZ = 3.0f;
constexpr float kTableTop = 0.88f;

Eigen::Matrix3f yaw_rotation(float yaw) {
  return Eigen::AngleAxisf(yaw, Vec3::UnitZ()).toRotationMatrix();
}

Material flat(float r, float g, float b) {
  return {Vec3(r, g, b), Texture::Flat};
}
Material fabric(const Vec3& c) {
  return {c, Texture::Fabric};
}
Material speckle(float r, float g, float b) {
  return {Vec3(r, g, b), Texture::Speckle};
}

// Adds primitives for one entity at a time; the current instance/class/part tag every primitive.
class SceneBuilder {
 public:
  explicit SceneBuilder(OrScene& scene) : scene_(scene) {}

  void begin_instance(int class_id) {
    instance_ = static_cast<int>(scene_.instance_class.size()) + 1;
    class_ = class_id;
    scene_.instance_class[instance_] = class_id;
    part_ = 0;
  }
  void begin_background() { instance_ = 0, class_ = 0, part_ = 0; }
  // The next primitive is part of the room's convex shell (casts no shadow inside the room).
  void shell() { shell_next_ = true; }
  void part(int p) { part_ = p; }

  void add(Shape shape, const Vec3& centre, const Vec3& half, const Material& m,
           const Eigen::Matrix3f& rotation = Eigen::Matrix3f::Identity()) {
    Primitive p;
    p.shape = shape;
    p.centre = centre;
    p.rotation = rotation;
    p.half_extents = half;
    p.material = m;
    p.instance = instance_;
    p.semantic = class_;
    p.part = part_;
    p.casts_shadow = !shell_next_;
    shell_next_ = false;
    scene_.primitives.push_back(p);
  }
  void box(const Vec3& c, const Vec3& half, const Material& m, float yaw = 0) {
    add(Shape::Box, c, half, m, yaw_rotation(yaw));
  }
  void cylinder(const Vec3& c, float radius, float half_height, const Material& m,
                const Eigen::Matrix3f& rotation = Eigen::Matrix3f::Identity()) {
    add(Shape::Cylinder, c, Vec3(radius, radius, half_height), m, rotation);
  }
  void sphere(const Vec3& c, float radius, const Material& m) {
    add(Shape::Sphere, c, Vec3::Constant(radius), m);
  }
  // Capsule whose core segment runs from a to b.
  void capsule(const Vec3& a, const Vec3& b, float radius, const Material& m) {
    const Vec3 axis = b - a;
    const Eigen::Matrix3f r =
        Eigen::Quaternionf::FromTwoVectors(Vec3::UnitZ(), axis.normalized()).toRotationMatrix();
    add(Shape::Capsule, 0.5f * (a + b), Vec3(radius, radius, 0.5f * axis.norm()), m, r);
  }

 private:
  OrScene& scene_;
  int instance_ = 0, class_ = 0, part_ = 0;
  bool shell_next_ = false;
};

void build_room(SceneBuilder& b) {
  b.begin_background();
  const float w = 0.1f;
  b.shell();
  b.box(Vec3(0, 0, -w), Vec3(kRoomX, kRoomY, w), {Vec3(0.58f, 0.64f, 0.62f), Texture::Tiles});
  b.shell();
  b.box(Vec3(0, 0, kRoomZ + w), Vec3(kRoomX, kRoomY, w), speckle(0.86f, 0.87f, 0.86f));
  const Material wall = speckle(0.72f, 0.80f, 0.78f);
  for (float s : {-1.f, 1.f}) {
    b.shell();
    b.box(Vec3(s * (kRoomX + w), 0, kRoomZ / 2), Vec3(w, kRoomY, kRoomZ / 2), wall);
    b.shell();
    b.box(Vec3(0, s * (kRoomY + w), kRoomZ / 2), Vec3(kRoomX, w, kRoomZ / 2), wall);
  }
  // Wall cabinets and a door: background structure that gives the walls some geometry.
  b.box(Vec3(-1.0f, kRoomY - 0.25f, 1.0f), Vec3(1.2f, 0.25f, 1.0f), speckle(0.80f, 0.80f, 0.78f));
  b.box(Vec3(2.2f, -kRoomY + 0.02f, 1.05f), Vec3(0.6f, 0.03f, 1.05f), flat(0.45f, 0.55f, 0.62f));
}

void build_operating_table(SceneBuilder& b, float x, float y) {
  b.begin_instance(kOperatingTable);
  const Material metal = speckle(0.35f, 0.37f, 0.40f);
  b.part(1);
  b.box(Vec3(x, y, 0.04f), Vec3(0.45f, 0.25f, 0.04f), metal);
  b.cylinder(Vec3(x, y, 0.42f), 0.13f, 0.36f, metal);
  b.part(2);
  b.box(Vec3(x, y, kTableTop - 0.04f), Vec3(1.05f, 0.29f, 0.04f), speckle(0.22f, 0.23f, 0.26f));
}

// Patient lying along +x (head at +x) under a green, deliberately textureless drape.
void build_patient(SceneBuilder& b, float x, float y, RandomStream& rng) {
  b.begin_instance(kPatient);
  const Material drape = flat(0.16f, 0.48f, 0.34f);
  b.part(1);
  b.add(Shape::Ellipsoid, Vec3(x - 0.1f, y, kTableTop + 0.10f), Vec3(0.80f, 0.25f, 0.12f), drape);
  const float overhang = static_cast<float>(rng.uniform(0.30f, 0.36f));
  b.box(Vec3(x - 0.15f, y, kTableTop + 0.01f), Vec3(0.85f, overhang, 0.025f), drape);
  b.part(2);
  b.sphere(Vec3(x + 0.88f, y, kTableTop + 0.13f), 0.11f, flat(0.85f, 0.68f, 0.56f));
}

struct PersonLook {
  Vec3 gown, cap, mask;
};

// A person standing at (x, y) facing `yaw`, built from capsules and spheres; `reach` in [0, 1]
// lifts the arms from hanging (0) to working over the table (1). Parts: 1 legs, 2 torso,
// 3 arms, 4 head (SAM's automatic masks split people along these).
void build_person(SceneBuilder& b, int class_id, float x, float y, float yaw, float scale,
                  float reach, const PersonLook& look) {
  b.begin_instance(class_id);
  const Vec3 base(x, y, 0);
  const Vec3 fwd(std::cos(yaw), std::sin(yaw), 0), left(-std::sin(yaw), std::cos(yaw), 0);
  auto at = [&](float f, float l, float z) {
    return Vec3(base + f * fwd + l * left + Vec3(0, 0, z * scale));
  };
  const Material gown = fabric(look.gown);
  b.part(1);
  for (float side : {-1.f, 1.f}) {
    b.capsule(at(0, 0.10f * side, 0.08f), at(0, 0.10f * side, 0.78f), 0.075f * scale, gown);
  }
  b.part(2);
  b.capsule(at(0, 0, 0.80f), at(0, 0, 1.36f), 0.20f * scale, gown);
  b.part(3);
  const float upper = 0.30f * scale, fore = 0.28f * scale;
  const float a1 = (10.f + 35.f * reach) * kPi / 180.f, a2 = (15.f + 65.f * reach) * kPi / 180.f;
  for (float side : {-1.f, 1.f}) {
    const Vec3 shoulder = at(0, 0.27f * side * scale, 1.40f);
    const Vec3 elbow = shoulder + upper * (std::sin(a1) * fwd - std::cos(a1) * Vec3::UnitZ());
    const Vec3 hand = elbow + fore * (std::sin(a2) * fwd - std::cos(a2) * Vec3::UnitZ()) -
                      0.08f * reach * side * left;
    b.capsule(shoulder, elbow, 0.055f * scale, gown);
    b.capsule(elbow, hand, 0.048f * scale, gown);
  }
  b.part(4);
  b.sphere(at(0, 0, 1.62f), 0.105f * scale, flat(0.82f, 0.66f, 0.55f));
  b.add(Shape::Ellipsoid, at(-0.01f, 0, 1.68f), Vec3(0.115f, 0.115f, 0.065f) * scale,
        fabric(look.cap));
  b.box(at(0.085f, 0, 1.585f), Vec3(0.035f, 0.075f, 0.05f) * scale,
        flat(look.mask.x(), look.mask.y(), look.mask.z()), yaw);
}

void build_anesthesia_machine(SceneBuilder& b, float x, float y, float yaw) {
  b.begin_instance(kAnesthesiaMachine);
  const Eigen::Matrix3f r = yaw_rotation(yaw);
  auto at = [&](float f, float l, float z) { return Vec3(Vec3(x, y, z) + r * Vec3(f, l, 0)); };
  b.part(1);
  b.box(at(0, 0, 0.65f), Vec3(0.32f, 0.38f, 0.60f), speckle(0.83f, 0.82f, 0.74f), yaw);
  b.part(2);
  b.box(at(0.05f, 0, 1.42f), Vec3(0.06f, 0.26f, 0.18f), flat(0.12f, 0.13f, 0.15f), yaw);
  b.part(3);
  for (float side : {-1.f, 1.f}) {
    b.cylinder(at(-0.25f, 0.28f * side, 0.45f), 0.07f, 0.40f, flat(0.20f, 0.45f, 0.25f));
  }
}

void build_instrument_table(SceneBuilder& b, float x, float y, float yaw) {
  b.begin_instance(kInstrumentTable);
  const Eigen::Matrix3f r = yaw_rotation(yaw);
  auto at = [&](float f, float l, float z) { return Vec3(Vec3(x, y, z) + r * Vec3(f, l, 0)); };
  b.part(1);
  for (float f : {-0.5f, 0.5f})
    for (float l : {-0.3f, 0.3f})
      b.cylinder(at(f, l, 0.45f), 0.02f, 0.45f, speckle(0.7f, 0.7f, 0.72f));
  b.part(2);
  b.box(at(0, 0, 0.92f), Vec3(0.62f, 0.38f, 0.03f), flat(0.25f, 0.42f, 0.62f), yaw);
  b.part(3);
  for (int i = 0; i < 5; ++i) {
    b.box(at(-0.4f + 0.2f * i, 0.1f * ((i % 2) ? 1.f : -1.f), 0.975f), Vec3(0.08f, 0.03f, 0.025f),
          speckle(0.78f, 0.79f, 0.82f), yaw);
  }
}

void build_secondary_table(SceneBuilder& b, float x, float y) {
  b.begin_instance(kSecondaryTable);
  b.part(1);
  b.cylinder(Vec3(x, y, 0.40f), 0.035f, 0.40f, speckle(0.7f, 0.7f, 0.72f));
  b.cylinder(Vec3(x, y, 0.03f), 0.25f, 0.03f, speckle(0.5f, 0.5f, 0.52f));
  b.part(2);
  b.box(Vec3(x, y, 0.83f), Vec3(0.35f, 0.25f, 0.03f), speckle(0.76f, 0.77f, 0.80f));
}

void build_monitor(SceneBuilder& b, float x, float y, float yaw) {
  b.begin_instance(kMonitor);
  const Eigen::Matrix3f r = yaw_rotation(yaw);
  b.part(1);
  b.cylinder(Vec3(x, y, 0.75f), 0.03f, 0.75f, speckle(0.6f, 0.6f, 0.62f));
  b.cylinder(Vec3(x, y, 0.03f), 0.28f, 0.03f, speckle(0.4f, 0.4f, 0.42f));
  b.part(2);
  b.box(Vec3(x, y, 1.55f), Vec3(0.04f, 0.36f, 0.24f), flat(0.10f, 0.10f, 0.12f), yaw);
  b.box(Vec3(Vec3(x, y, 1.55f) + r * Vec3(0.045f, 0, 0)), Vec3(0.005f, 0.32f, 0.20f),
        flat(0.18f, 0.30f, 0.42f), yaw);
}

// Ceiling-mounted lamp: an arm from the ceiling and a tilted disc over (x, y).
void build_surgical_lamp(SceneBuilder& b, const Vec3& head, float tilt) {
  b.begin_instance(kSurgicalLamp);
  b.part(1);
  const Vec3 mount(head.x() + 0.5f, head.y() + 0.3f, kRoomZ);
  b.capsule(mount, Vec3(mount.x(), mount.y(), head.z() + 0.45f), 0.035f, speckle(0.8f, 0.8f, 0.8f));
  b.capsule(Vec3(mount.x(), mount.y(), head.z() + 0.45f), head + Vec3(0, 0, 0.08f), 0.03f,
            speckle(0.8f, 0.8f, 0.8f));
  b.part(2);
  const Eigen::Matrix3f r = Eigen::AngleAxisf(tilt, Vec3::UnitY()).toRotationMatrix();
  b.cylinder(head, 0.34f, 0.07f, speckle(0.90f, 0.90f, 0.88f), r);
}

// Mobile C-arm: a base on wheels and a C of capsules in the plane across the table.
void build_c_arm(SceneBuilder& b, float x, float y, float yaw) {
  b.begin_instance(kCArm);
  const Eigen::Matrix3f r = yaw_rotation(yaw);
  auto at = [&](float f, float l, float z) { return Vec3(Vec3(x, y, z) + r * Vec3(f, l, 0)); };
  const Material body = speckle(0.88f, 0.88f, 0.84f);
  b.part(1);
  b.box(at(0, 0, 0.55f), Vec3(0.40f, 0.30f, 0.55f), body, yaw);
  b.part(2);
  // The C opens towards +l (the table side), centred 1.1 m from the base.
  const float radius = 0.55f;
  const Vec3 centre = at(0, 1.1f, 1.05f);
  const Vec3 across = r * Vec3(0, 1, 0);
  Vec3 prev = centre;
  for (int i = 0; i <= 6; ++i) {
    const float a = -0.5f * kPi + kPi * i / 6.f;
    const Vec3 p = centre + radius * (-std::cos(a) * across + std::sin(a) * Vec3::UnitZ());
    if (i > 0) b.capsule(prev, p, 0.06f, body);
    prev = p;
  }
  b.capsule(at(0, 0.30f, 1.05f), centre - radius * across, 0.07f, body);
  b.part(3);
  b.cylinder(centre + radius * Vec3::UnitZ() - Vec3(0, 0, 0.08f), 0.18f, 0.06f,
             flat(0.25f, 0.25f, 0.28f));
}

// Camera at `position` looking at `target` with world z up: rows of R are the camera axes
// (x right, y down, z forward) expressed in world coordinates.
Pose look_at(const Vec3& position, const Vec3& target) {
  const Eigen::Vector3d c = position.cast<double>();
  const Eigen::Vector3d forward = (target.cast<double>() - c).normalized();
  const Eigen::Vector3d right = forward.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d down = forward.cross(right);
  Pose pose;
  pose.R.row(0) = right;
  pose.R.row(1) = down;
  pose.R.row(2) = forward;
  pose.t = -pose.R * c;
  return pose;
}

void place_cameras(OrScene& scene, const OrSceneOptions& o) {
  RandomStream rng(stream_seed(o.seed, kCameraStream));
  const double fx = 0.5 * o.width / std::tan(0.5 * o.horizontal_fov_deg * M_PI / 180.0);
  const int test = held_out_count(o.views);
  for (int i = 0; i < o.views; ++i) {
    // Corners first (45 degrees), then evenly around the room's rectangle.
    const float a = kPi / 4 + 2 * kPi * i / o.views;
    const float s = 1.f / std::max(std::abs(std::cos(a)), std::abs(std::sin(a)));
    const Vec3 position((kRoomX - 0.35f) * std::cos(a) * s, (kRoomY - 0.35f) * std::sin(a) * s,
                        static_cast<float>(rng.uniform(2.55, 2.75)));
    const Vec3 target = scene.look_at + Vec3(static_cast<float>(rng.uniform(-0.2, 0.2)),
                                             static_cast<float>(rng.uniform(-0.2, 0.2)), 0);
    OrCamera cam;
    cam.name = "cam_" + std::string(i < 10 ? "0" : "") + std::to_string(i);
    cam.camera.width = o.width;
    cam.camera.height = o.height;
    cam.camera.fx = cam.camera.fy = fx;
    cam.camera.cx = 0.5 * o.width;
    cam.camera.cy = 0.5 * o.height;
    cam.pose = look_at(position, target);
    cam.held_out = i >= o.views - test;
    scene.cameras.push_back(cam);
  }
}

}  // namespace

const std::map<int, std::string>& or_class_names() {
  static const std::map<int, std::string> names = {
      {kOperatingTable, "operating table"},
      {kPatient, "patient"},
      {kHeadSurgeon, "head surgeon"},
      {kAssistantSurgeon, "assistant surgeon"},
      {kCirculatingNurse, "circulating nurse"},
      {kAnaesthetist, "anaesthetist"},
      {kAnesthesiaMachine, "anesthesia machine"},
      {kInstrumentTable, "instrument table"},
      {kSecondaryTable, "secondary table"},
      {kMonitor, "monitor"},
      {kSurgicalLamp, "surgical lamp"},
      {kCArm, "C-arm"},
  };
  return names;
}

bool is_look_alike_class(int c) {
  return c == kHeadSurgeon || c == kAssistantSurgeon || c == kCirculatingNurse ||
         c == kAnaesthetist;
}

const EnumNames<OrPhase>& or_phase_names() {
  static const EnumNames<OrPhase> names = {{OrPhase::Preparation, "preparation"},
                                           {OrPhase::Surgery, "surgery"},
                                           {OrPhase::Closing, "closing"}};
  return names;
}

const std::string& to_string(OrPhase phase) {
  return enum_name(phase, or_phase_names());
}

OrPhase parse_or_phase(const std::string& name) {
  return parse_enum(name, or_phase_names(), "phase");
}

int held_out_count(int views) {
  return std::max(1, views / 5);
}

void check_or_scene_options(const OrSceneOptions& o) {
  if (o.views < 4 || o.views > 8) {
    throw std::invalid_argument("views must be 4..8, got " + std::to_string(o.views));
  }
  if (o.width < 16 || o.height < 16) {
    throw std::invalid_argument("image size must be at least 16x16, got " +
                                std::to_string(o.width) + "x" + std::to_string(o.height));
  }
}

OrScene make_or_scene(const OrSceneOptions& o) {
  check_or_scene_options(o);
  OrScene scene;
  RandomStream rng(stream_seed(o.seed, kLayoutStream));
  auto jitter = [&](double r) { return static_cast<float>(rng.uniform(-r, r)); };
  SceneBuilder b(scene);
  build_room(b);

  const float tx = jitter(0.3f), ty = jitter(0.2f);
  scene.look_at = Vec3(tx, ty, kTableTop);
  build_operating_table(b, tx, ty);
  build_patient(b, tx, ty, rng);

  // Sides: which side of the table the head surgeon stands on, where the machine and the
  // instrument table go; mirrored by the seed so layouts differ.
  const float side = rng.chance(0.5) ? 1.f : -1.f;
  const float nurse_side = rng.chance(0.5) ? 1.f : -1.f;
  const bool preparation = o.phase == OrPhase::Preparation;
  const bool surgery = o.phase == OrPhase::Surgery;
  const float reach = preparation ? 0.f : (surgery ? 1.f : 0.6f);
  const Vec3 gown(0.30f, 0.48f, 0.62f), cap(0.28f, 0.45f, 0.66f), mask(0.80f, 0.86f, 0.90f);
  auto look = [&](const Vec3& g, const Vec3& c) {
    const Vec3 tint(jitter(0.03f), jitter(0.03f), jitter(0.03f));
    return PersonLook{g + tint, c, mask};
  };
  auto height = [&]() { return 1.f + jitter(0.07f); };

  const float gap = preparation ? 0.9f : 0.55f;
  const float hs_x = tx + jitter(0.3f), as_x = tx + jitter(0.3f) - 0.15f;
  build_person(b, kHeadSurgeon, hs_x, ty - side * (0.29f + gap), side * kPi / 2 + jitter(0.2f),
               height(), reach, look(gown, cap));
  build_person(b, kAssistantSurgeon, as_x, ty + side * (0.29f + gap),
               -side * kPi / 2 + jitter(0.2f), height(), reach, look(gown, cap));
  // Instrument table at the foot end on the nurse's side; the nurse stands beside it (nearer
  // the table while closing, counting instruments).
  const float it_x = tx - 1.55f + jitter(0.15f), it_y = ty + nurse_side * (1.2f + jitter(0.1f));
  build_instrument_table(b, it_x, it_y, jitter(0.2f));
  const float nurse_dy = o.phase == OrPhase::Closing ? -0.55f : 0.6f;
  build_person(b, kCirculatingNurse, it_x + jitter(0.2f), it_y + nurse_side * nurse_dy,
               -nurse_side * kPi / 2 * (nurse_dy > 0 ? 1.f : -1.f) + jitter(0.3f), height(), 0.3f,
               look(gown, Vec3(0.35f, 0.50f, 0.70f)));
  // Anaesthetist at the head end by the machine, in scrubs of a slightly different shade.
  const float machine_side = rng.chance(0.5) ? 1.f : -1.f;
  const float am_x = tx + 1.95f + jitter(0.1f), am_y = ty + machine_side * (0.75f + jitter(0.1f));
  build_anesthesia_machine(b, am_x, am_y, kPi + jitter(0.2f));
  build_person(b, kAnaesthetist, tx + 1.40f + jitter(0.1f), ty - machine_side * 0.1f + jitter(0.1f),
               kPi + jitter(0.4f), height(), 0.2f, look(Vec3(0.27f, 0.50f, 0.55f), cap));
  build_secondary_table(b, tx - 0.9f + jitter(0.2f), ty - nurse_side * (1.35f + jitter(0.1f)));
  build_monitor(b, tx + 0.5f + jitter(0.3f), ty - machine_side * 1.75f,
                machine_side * kPi / 2 + jitter(0.2f));
  if (rng.chance(0.5)) {
    build_monitor(b, -kRoomX + 0.6f, ty + jitter(1.0f), jitter(0.3f));
  }
  const Vec3 lamp = preparation ? Vec3(tx + 0.8f, ty + 1.0f, 2.25f)
                                : Vec3(tx + jitter(0.3f), ty + jitter(0.2f), 2.05f);
  build_surgical_lamp(b, lamp, jitter(0.3f));
  // The C-arm is wheeled to the table for imaging during surgery, parked by the wall otherwise.
  if (surgery) {
    build_c_arm(b, tx - 1.0f, ty - side * 1.5f, side > 0 ? 0.f : kPi);
  } else {
    build_c_arm(b, -kRoomX + 0.8f, -side * (kRoomY - 0.8f), side > 0 ? 0.f : kPi);
  }

  scene.lights = {{Vec3(-1.5f, -1.0f, 2.6f), 0.35f},
                  {Vec3(1.5f, 1.2f, 2.6f), 0.35f},
                  {lamp - Vec3(0, 0, 0.15f), 0.35f}};
  place_cameras(scene, o);
  return scene;
}

}  // namespace gslift::synth
