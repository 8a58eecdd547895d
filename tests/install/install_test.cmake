# ctest "install.EmbedExample": installs this build into a fresh temporary prefix, checks
# what was installed (the CLI, libridge and its two headers, the CMake package, nothing
# internal; libridge exports only the ridge API), then builds examples/embed against the
# *installed* package alone and runs both programs on a real fixture.
#   cmake -DBUILD_DIR=... -DSOURCE_DIR=... -DWORK_DIR=... -DFIXTURE=... [-DEXAMPLE_FLAGS=...]
#         -DGENERATOR=... -DCXX=... -DLIBDIR=lib -P install_test.cmake
foreach(var BUILD_DIR SOURCE_DIR WORK_DIR FIXTURE GENERATOR CXX LIBDIR)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "install_test.cmake: ${var} is not set")
  endif()
endforeach()

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message(STATUS "$ ${ARGN}\n${out}${err}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}")
  endif()
  set(run_output "${out}" PARENT_SCOPE)
endfunction()

# WORK_DIR is inside the build tree and belongs to this test alone.
file(REMOVE_RECURSE ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)
file(MAKE_DIRECTORY ${WORK_DIR}/out)

run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})

foreach(path bin/ridge include/ridge/ridge.h include/ridge/error.h ${LIBDIR}/pkgconfig/ridge.pc
             ${LIBDIR}/cmake/ridge/ridgeConfig.cmake
             ${LIBDIR}/cmake/ridge/ridgeConfigVersion.cmake
             ${LIBDIR}/cmake/ridge/ridgeTargets.cmake)
  if(NOT EXISTS ${prefix}/${path})
    message(FATAL_ERROR "not installed: ${path}")
  endif()
endforeach()
file(GLOB libs ${prefix}/${LIBDIR}/libridge.so.*)
if(NOT libs)
  message(FATAL_ERROR "not installed: ${LIBDIR}/libridge.so.*")
endif()
# Internal headers and stage libraries stay out of the prefix.
file(GLOB_RECURSE headers RELATIVE ${prefix}/include ${prefix}/include/*)
if(NOT headers STREQUAL "ridge/error.h;ridge/ridge.h")
  message(FATAL_ERROR "installed headers must be ridge/error.h and ridge/ridge.h only, got: ${headers}")
endif()
file(GLOB_RECURSE archives ${prefix}/*.a)
if(archives)
  message(FATAL_ERROR "static stage libraries installed: ${archives}")
endif()

# The shared library's dynamic symbols: everything it defines is ridge's public API (C++
# names in namespace ridge that ridge.h declares), so internals cannot be linked against.
list(GET libs 0 lib)
run(nm -D -C --defined-only ${lib})
string(REPLACE "\n" ";" symbols "${run_output}")
set(public 0)
foreach(line IN LISTS symbols)
  if(line STREQUAL "")
    continue()
  endif()
  string(REGEX REPLACE "^[0-9a-f]+ [A-Za-z] " "" name "${line}")
  if(name MATCHES "^(_init|_fini|_edata|_end|__bss_start)$")
    continue()
  endif()
  # Public: ridge::<Name> (capitalised types and their members, typeinfo and vtables) and
  # the free functions ridge.h declares.
  if(name MATCHES "(^|[ :])ridge::(Error|Cancelled|Terrain|Renderer|build|verify|renderPng|versionString)[(:]"
     OR name MATCHES "^ridge::lodSchemes(\\[abi:cxx11\\])?\\(\\)$"
     OR name MATCHES "^(typeinfo|typeinfo name|vtable) for ridge::(Error|Cancelled)$")
    math(EXPR public "${public} + 1")
  else()
    message(FATAL_ERROR "libridge exports a symbol that is not ridge's API: ${name}")
  endif()
endforeach()
if(public LESS 10)
  message(FATAL_ERROR "libridge exports only ${public} API symbols")
endif()

# A consumer that knows only the prefix.
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/examples/embed -B ${WORK_DIR}/example -G ${GENERATOR}
    -DCMAKE_CXX_COMPILER=${CXX} -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_BUILD_TYPE=Release
    "-DCMAKE_CXX_FLAGS=${EXAMPLE_FLAGS}" "-DCMAKE_EXE_LINKER_FLAGS=${EXAMPLE_FLAGS}")
run(${CMAKE_COMMAND} --build ${WORK_DIR}/example)
run(${WORK_DIR}/example/ridge_embed ${FIXTURE} ${WORK_DIR}/out)
foreach(expected "verify: ok" "rendered" "refused as expected")
  string(FIND "${run_output}" "${expected}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "ridge_embed did not print \"${expected}\"")
  endif()
endforeach()
if(NOT EXISTS ${WORK_DIR}/out/terrain.png)
  message(FATAL_ERROR "ridge_embed wrote no PNG")
endif()
# pkg-config, as a non-CMake build would use it: compile and link embed.cpp by hand, then run
# it without arguments (it prints its usage and exits 2, having loaded libridge).
find_program(PKG_CONFIG pkg-config REQUIRED)
set(ENV{PKG_CONFIG_PATH} ${prefix}/${LIBDIR}/pkgconfig)
run(${PKG_CONFIG} --cflags --libs ridge)
string(STRIP "${run_output}" pc_flags)
separate_arguments(pc_flags UNIX_COMMAND "${pc_flags}")
separate_arguments(example_flags UNIX_COMMAND "${EXAMPLE_FLAGS}")
run(${CXX} -std=c++20 ${example_flags} ${SOURCE_DIR}/examples/embed/embed.cpp ${pc_flags}
    -Wl,-rpath,${prefix}/${LIBDIR} -o ${WORK_DIR}/embed_pkgconfig)
execute_process(COMMAND ${WORK_DIR}/embed_pkgconfig RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 2 OR NOT err MATCHES "usage:")
  message(FATAL_ERROR "embed.cpp built with pkg-config: exit ${rc}, ${err}")
endif()

if(EXISTS ${WORK_DIR}/example/ridge_embed_gl)
  run(${WORK_DIR}/example/ridge_embed_gl ${WORK_DIR}/out/terrain.ridge)
else()
  message(FATAL_ERROR "ridge_embed_gl was not built (EGL and epoxy are ridge's own dependencies)")
endif()
