// Links only Kilohertz::haptic from an install prefix (its library finds libkhz_contact.so and
// libkhz_reduced.so by its own run path): the coupling renders a contact's reaction.
#include <khz/haptic/coupling/virtual_coupling.hpp>
#include <khz/haptic/version.hpp>

#include <cstring>
#include <iostream>

int main() {
  if (std::strcmp(khz::haptic::library_version(), KHZ_HAPTIC_VERSION_STRING) != 0) {
    std::cerr << "libkhz_haptic " << khz::haptic::library_version() << " differs from its headers' "
              << KHZ_HAPTIC_VERSION_STRING << "\n";
    return 1;
  }
  // A floor pushing the held object up with 2 N and a stiffness of 1000 N/m: the coupling moves
  // the simulation object up and renders the reaction to the hand.
  khz::contact::ContactWrench contact;
  contact.force = Eigen::Vector3d(0.0, 0.0, 2.0);
  contact.force_by_translation(2, 2) = -1000.0;
  khz::haptic::VirtualCoupling coupling(khz::haptic::CouplingOptions{});
  const khz::haptic::CouplingStep step = coupling.step({}, contact);
  if (!step.valid || !(step.simulation.position.z() > 0.0) || !(step.rendered.force.z() > 0.0)) {
    std::cerr << "installed libhaptic's coupling did not follow the contact\n";
    return 1;
  }
  std::cout << "Kilohertz::haptic " << khz::haptic::library_version() << ": rendered "
            << step.rendered.force.z() << " N up\n";
  return 0;
}
