# glint-image command-line tests (cli_test.cpp) run the built binary, whose path they get here.
add_dependencies(image_tests glint-image)
target_compile_definitions(image_tests PRIVATE GLINT_IMAGE_CLI="$<TARGET_FILE:glint-image>")
target_link_libraries(image_tests PRIVATE nlohmann_json::nlohmann_json)
