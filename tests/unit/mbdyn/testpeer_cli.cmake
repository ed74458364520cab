# The mbdyn_testpeer executable as later Python/LAMMPS tests will use it: it must print its
# usage, and it must refuse a port at or below 5000 as MBDyn's parser does (spec §1).
execute_process(COMMAND ${PEER} --help RESULT_VARIABLE rc OUTPUT_VARIABLE out)
if(NOT rc EQUAL 0 OR NOT out MATCHES "--coupling loose\\|tight\\|none")
  message(FATAL_ERROR "mbdyn_testpeer --help failed (${rc}): ${out}")
endif()
execute_process(COMMAND ${PEER} --port 4000 RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 2 OR NOT err MATCHES "above 5000")
  message(FATAL_ERROR "mbdyn_testpeer accepted port 4000 (${rc}): ${err}")
endif()
# A value that is not a number is a usage error (status 2) naming the option, not an abort (134).
foreach(bad "--nodes;abc" "--nodes;0" "--nodes;3x" "--steps;-1" "--dt;nan" "--port;99999")
  execute_process(COMMAND ${PEER} --path /tmp/dembridge-mbdyn-cli-$ENV{USER}-bad.sock ${bad} --accept-timeout 0.2
                  RESULT_VARIABLE rc ERROR_VARIABLE err TIMEOUT 20)
  list(GET bad 0 opt)
  if(NOT rc EQUAL 2 OR NOT err MATCHES "${opt} expects")
    message(FATAL_ERROR "mbdyn_testpeer ${bad}: status ${rc} (expected 2 and a usage error naming ${opt}): ${err}")
  endif()
endforeach()
# Nobody connects: it must give up within its accept timeout with MBDyn's error status 1.
execute_process(COMMAND ${PEER} --path /tmp/dembridge-mbdyn-cli-$ENV{USER}-nobody.sock --accept-timeout 0.5
                RESULT_VARIABLE rc OUTPUT_VARIABLE out TIMEOUT 20)
if(NOT rc EQUAL 1 OR NOT out MATCHES "no peer connected")
  message(FATAL_ERROR "mbdyn_testpeer without a client: status ${rc}: ${out}")
endif()
# A Unix-socket peer announces where it listens before blocking in accept.
execute_process(COMMAND ${PEER} --path /tmp/dembridge-mbdyn-cli-$ENV{USER}-announce.sock --accept-timeout 0.2
                RESULT_VARIABLE rc OUTPUT_VARIABLE out TIMEOUT 20)
if(NOT out MATCHES "listening on unix socket /tmp/dembridge-mbdyn-cli-.*-announce.sock")
  message(FATAL_ERROR "mbdyn_testpeer did not announce its socket: ${out}")
endif()
