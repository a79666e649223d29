# Compiles GLSL to SPIR-V at build time with glslangValidator. Dependency files make an edit
# of an included header rebuild every shader that includes it (Ninja and Makefiles).
find_program(GLSLANG_VALIDATOR glslangValidator REQUIRED)

set(DDGI_SHADER_INCLUDE_DIR ${CMAKE_SOURCE_DIR}/shaders)

# ddgi_compile_shader(<out-var> SOURCE <file> STAGE <comp|rgen|rchit|rahit|rmiss>
#                     OUTPUT <name.spv> [DEFINES A=1 B ...])
function(ddgi_compile_shader out_var)
  cmake_parse_arguments(ARG "" "SOURCE;STAGE;OUTPUT" "DEFINES" ${ARGN})
  set(output ${DDGI_SHADER_OUTPUT_DIR}/${ARG_OUTPUT})
  set(depfile ${CMAKE_CURRENT_BINARY_DIR}/${ARG_OUTPUT}.d)
  set(defines "")
  foreach(def IN LISTS ARG_DEFINES)
    list(APPEND defines "-D${def}")
  endforeach()
  set(depfile_args DEPFILE ${depfile})
  add_custom_command(
    OUTPUT ${output}
    COMMAND ${CMAKE_COMMAND} -E make_directory ${DDGI_SHADER_OUTPUT_DIR}
    COMMAND ${GLSLANG_VALIDATOR} --quiet --target-env vulkan1.2 -g -S ${ARG_STAGE}
            -I${DDGI_SHADER_INCLUDE_DIR} ${defines} --depfile ${depfile}
            -o ${output} ${ARG_SOURCE}
    MAIN_DEPENDENCY ${ARG_SOURCE}
    ${depfile_args}
    COMMENT "SPIR-V ${ARG_OUTPUT}"
    VERBATIM)
  set(${out_var} ${${out_var}} ${output} PARENT_SCOPE)
endfunction()

# A tracing kernel is written once and compiled twice: as a compute shader with ray queries
# and as a ray-generation shader for ray-tracing pipelines.
# ddgi_compile_tracing_kernel(<out-var> <name> <source> [DEFINES A=1 ...])
function(ddgi_compile_tracing_kernel out_var name source)
  cmake_parse_arguments(ARG "" "" "DEFINES" ${ARGN})
  ddgi_compile_shader(${out_var} SOURCE ${source} STAGE comp OUTPUT ${name}.query.comp.spv
                      DEFINES DDGI_BACKEND_QUERY=1 ${ARG_DEFINES})
  ddgi_compile_shader(${out_var} SOURCE ${source} STAGE rgen OUTPUT ${name}.pipeline.rgen.spv
                      DEFINES DDGI_BACKEND_PIPELINE=1 ${ARG_DEFINES})
  set(${out_var} ${${out_var}} PARENT_SCOPE)
endfunction()
