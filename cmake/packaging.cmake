# Installation (GNUInstallDirs layout) and the Debian package (CPack DEB). docs/install.md explains
# the layout, the package's dependencies and the licence.
#
#   <prefix>/bin/fogpipe
#   <prefix>/share/fogpipe/schemas/         the layouts `fogpipe validate` checks against
#   <prefix>/share/fogpipe/scripts/         report.py, plot_sweep.py, campaign_report.py, slurm/
#   <prefix>/share/doc/fogpipe/             LICENSE, copyright (Debian format), README.md
set(FOGPIPE_INSTALL_DATADIR "${CMAKE_INSTALL_DATADIR}/fogpipe")
# `cmake --install` and `cpack` install what is built and do not first build every test and
# benchmark (the `all` target): build the `fogpipe` target before installing.
set(CMAKE_SKIP_INSTALL_ALL_DEPENDENCY ON)

install(TARGETS fogpipe RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/schemas/ DESTINATION ${FOGPIPE_INSTALL_SCHEMASDIR})
install(PROGRAMS ${PROJECT_SOURCE_DIR}/scripts/report.py ${PROJECT_SOURCE_DIR}/scripts/plot_sweep.py
                 ${PROJECT_SOURCE_DIR}/scripts/campaign_report.py
        DESTINATION ${FOGPIPE_INSTALL_DATADIR}/scripts)
install(PROGRAMS
          ${PROJECT_SOURCE_DIR}/scripts/slurm/submit_campaign.sh
          ${PROJECT_SOURCE_DIR}/scripts/slurm/fogpipe_array.sbatch
          ${PROJECT_SOURCE_DIR}/scripts/slurm/fogpipe_merge.sbatch
          ${PROJECT_SOURCE_DIR}/scripts/slurm/check_campaign.py
          ${PROJECT_SOURCE_DIR}/scripts/slurm/local_cluster.sh
        DESTINATION ${FOGPIPE_INSTALL_DATADIR}/scripts/slurm)
install(FILES ${PROJECT_SOURCE_DIR}/scripts/slurm/README.md
        DESTINATION ${FOGPIPE_INSTALL_DATADIR}/scripts/slurm)
install(FILES ${PROJECT_SOURCE_DIR}/LICENSE ${PROJECT_SOURCE_DIR}/packaging/copyright
              ${PROJECT_SOURCE_DIR}/README.md
        DESTINATION ${CMAKE_INSTALL_DOCDIR})

# ---------------------------------------------------------------- Debian package
if(FOGPIPE_NATIVE)
  message(WARNING "FOGPIPE_NATIVE=ON: a package built here runs only on CPUs with this machine's "
                  "instruction set. Configure with -DFOGPIPE_NATIVE=OFF to build a portable package.")
endif()
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME fogpipe)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_VENDOR "The fogpipe authors")
set(CPACK_PACKAGE_CONTACT "The fogpipe authors <fogpipe@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "${PROJECT_DESCRIPTION}")
set(CPACK_RESOURCE_FILE_LICENSE ${PROJECT_SOURCE_DIR}/LICENSE)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_DESCRIPTION
    "Batch pipeline for fiber-optic gyroscope test campaigns\n"
    "Decomposes static gyro recordings (HDF5) by EMD, fits an AR model and a Kalman filter per\n"
    "intrinsic mode function, and reports Allan variance tables and the IEEE Std 952 noise terms.")
# The Debian 12 packages of the shared libraries the binary links (objdump -p: NEEDED, dpkg -S),
# with the minimum versions dpkg-shlibdeps derives from the symbols used. Written out rather than
# computed at packaging time so that the package does not depend on the build machine's versions;
# tests/pipeline/packaging/package_test.sh fails when a NEEDED library's package is missing here.
string(CONCAT CPACK_DEBIAN_PACKAGE_DEPENDS
    "libc6 (>= 2.35), libgcc-s1 (>= 4.0), libhdf5-103-1, libhdf5-cpp-103-1 (>= 1.10.5), "
    "libssl3 (>= 3.0.0), libstdc++6 (>= 11), libtbb12 (>= 2021.4.0), libtomlplusplus3 (>= 3.2.0), "
    "zlib1g (>= 1:1.2.0)")
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "python3, python3-numpy, python3-h5py, python3-matplotlib")
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "slurm-client")
include(CPack)
