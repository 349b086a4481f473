program main
    implicit none
end program main
