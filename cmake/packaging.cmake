# What `cmake --install` and `cpack -G DEB` ship besides the binary and its data: the documents
# (every one the README links), the man page and the Debian changelog gzipped as Debian policy
# asks (12.3, 12.7), the copyright file in the machine-readable format (DEP-5), and the package's
# own fields.
set(packaging_dir ${CMAKE_BINARY_DIR}/packaging)
file(MAKE_DIRECTORY ${packaging_dir})
configure_file(${CMAKE_SOURCE_DIR}/packaging/changelog.in ${packaging_dir}/changelog @ONLY)
# -n: no name or time in the gzip header, so the same input gives the same bytes.
add_custom_command(
  OUTPUT ${packaging_dir}/mblab.1.gz ${packaging_dir}/changelog.gz
  COMMAND gzip -9n -c ${CMAKE_SOURCE_DIR}/docs/mblab.1 > ${packaging_dir}/mblab.1.gz
  COMMAND gzip -9n -c ${packaging_dir}/changelog > ${packaging_dir}/changelog.gz
  DEPENDS ${CMAKE_SOURCE_DIR}/docs/mblab.1 ${packaging_dir}/changelog
  COMMENT "Compressing the man page and the changelog"
  VERBATIM)
add_custom_target(mblab_packaging ALL DEPENDS ${packaging_dir}/mblab.1.gz ${packaging_dir}/changelog.gz)

install(FILES ${CMAKE_SOURCE_DIR}/README.md ${CMAKE_SOURCE_DIR}/LICENSE
        ${CMAKE_SOURCE_DIR}/packaging/copyright ${packaging_dir}/changelog.gz
        DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(DIRECTORY ${CMAKE_SOURCE_DIR}/docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR}
        FILES_MATCHING PATTERN "*.md" PATTERN "*.yaml")
install(FILES ${packaging_dir}/mblab.1.gz DESTINATION ${CMAKE_INSTALL_MANDIR}/man1)
install(FILES ${CMAKE_SOURCE_DIR}/completion/mblab.bash
        DESTINATION ${CMAKE_INSTALL_DATADIR}/bash-completion/completions RENAME mblab)

# `cpack -G DEB` from the build tree: a Debian package installing under /usr, its library
# dependencies found by dpkg-shlibdeps.
set(CPACK_PACKAGE_NAME mblab)
set(CPACK_PACKAGE_VENDOR "the mblab authors")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "Modbus conformance lab: tester, reference device, load test and client")
# The extended description; CPack puts the summary above it as the synopsis.
set(CPACK_PACKAGE_DESCRIPTION
    "mblab tests Modbus/TCP, Modbus/TCP Security, RTU and ASCII devices against
the public Modbus specifications, serves a reference device (with a dashboard,
a REST API and a traffic log), generates load, fuzzes, scans, and reads and
writes devices from the command line.")
set(CPACK_PACKAGE_CONTACT "mblab developers <mblab@users.noreply.github.com>")
set(CPACK_RESOURCE_FILE_LICENSE ${CMAKE_SOURCE_DIR}/LICENSE)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION net)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# The completion is installed whatever; bash-completion is what loads it.
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS bash-completion)
include(CPack)
