// URDF models through urdfdom: loading any fixed-base serial or tree robot, and exporting any
// Model.
#pragma once

#include <string>
#include <vector>

#include "core/floating/floating_model.hpp"
#include "core/model.hpp"

namespace dynid {

struct UrdfOptions {
  /// Enable drive terms ia, fv, fc. The values always come from the file: Fv from <dynamics
  /// damping>, Fc from <dynamics friction>, the others 0.
  bool drives = false;
  /// Turn warnings (a moving link without <inertial>) into errors.
  bool strict = false;
  /// Moving joints treated as fixed at their zero position (a gripper's fingers on an arm being
  /// identified): their child links merge into the parent body like a fixed joint's. Each must
  /// name a revolute, continuous or prismatic joint of the file (ParseError otherwise).
  std::vector<std::string> fixed_joints = {};
};

/// Loads a URDF file. The root link is the fixed base; revolute, continuous and prismatic joints
/// become dynid joints in topological order, earliest in the file first (a file that lists parents
/// before children keeps its joint order); fixed joints are merged into their parent body (inertia
/// transformed by the joint origin, grandchildren re-attached).
/// Throws ParseError naming the file, the line when known and the element ("joint 'elbow'") for:
/// XML or urdfdom errors (unknown parents, cycles, several roots, missing <mass>), floating or
/// planar joints, negative masses, non-finite numbers, a zero joint axis. Warnings (unless strict)
/// are appended to `warnings` when given.
Model loadUrdf(const std::string& path, const UrdfOptions& options = {},
               std::vector<std::string>* warnings = nullptr);

/// Same as loadUrdf, from URDF text; `file` names the source in errors.
Model parseUrdf(const std::string& text, const std::string& file, const UrdfOptions& options = {},
                std::vector<std::string>* warnings = nullptr);

/// Loads a floating-base robot (core/floating/floating_model.hpp): the root link and every link
/// fixed to it are the base body (its frame the root's), the moving joints the limbs as loadUrdf
/// builds them. A root that holds only a floating joint is the world: the base is that joint's
/// child. The model's frames name every link (moving, merged or the base) with its body and
/// placement, for contacts and sensors. Throws ParseError as loadUrdf does, and for a floating
/// joint anywhere but at the root.
FloatingModel loadFloatingUrdf(const std::string& path, const UrdfOptions& options = {},
                               std::vector<std::string>* warnings = nullptr);
FloatingModel parseFloatingUrdf(const std::string& text, const std::string& file,
                                const UrdfOptions& options = {},
                                std::vector<std::string>* warnings = nullptr);

/// The model as URDF text, numbers in shortest round-trip form. URDF link frames are the joint
/// frames: for models with a body placement after the joint (Denavit-Hartenberg), each link's
/// inertia is re-expressed in its joint frame, so the dynamics are identical but the standard
/// parameters of a reloaded model are those of the joint frames. Drives export as
/// <dynamics damping="Fv" friction="Fc"/>; Ia, Fo, Fa and gravity have no URDF element and are
/// lost.
std::string modelToUrdf(const Model& model);

/// What a URDF export of `model` cannot carry, one sentence each: the enabled drive terms with no
/// URDF attribute (the drive-term table's urdf_dynamics: Ia, Fo, Fa, Fs), and gravity other than
/// -9.81 m/s^2 along z (URDF has none; a reader assumes it).
std::vector<std::string> urdfCannotCarry(const Model& model);

/// `<dynamics damping="Fv" friction="Fc"/>`: the drive terms the drive-term table maps to URDF
/// attributes (DriveTermInfo::urdf_dynamics), in table order, from `drive`.
std::string urdfDynamicsElement(const DriveParameters<double>& drive);

/// The index of the '>' that closes an XML tag whose attributes start at `from`, skipping quoted
/// attribute values (which may hold '>'); text.size() when the tag is unterminated.
std::size_t xmlTagEnd(const std::string& text, std::size_t from);

}  // namespace dynid
